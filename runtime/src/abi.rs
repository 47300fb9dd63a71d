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
pub const SCENE_VERSION: u32 = 3;
/// Bytes of the ray record the prelude's `trax::stream` writes and reads (thesis §3.2.1:
/// origin and direction 24, ray state 20, traversal stack 4), and the default of the chip
/// config's `stream_memory.ray_bytes`.
pub const STREAM_RECORD_BYTES: u32 = 48;

/// The global register from which `trax::scene::pixel_share` hands out pixels (one
/// `atomic_add` per pixel block). Sampled simulation (`trax run --sample`) follows a
/// frame's progress along it.
pub const PIXEL_COUNTER_REG: u32 = 255;

/// The global registers in which `trax::declare_work` (C: `trax_declare_work`) records a
/// kernel's work counter for sampled simulation: `WORK_COUNTER_REG` holds the counter's
/// register plus one (0: nothing declared), `WORK_ITEMS_REG` the items it hands out.
/// Written once, by thread 0, before the first item is taken.
pub const WORK_COUNTER_REG: u32 = 254;
/// See [`WORK_COUNTER_REG`].
pub const WORK_ITEMS_REG: u32 = 253;

#[macro_use]
pub mod encode;

pub use encode::{decode, encode, Field, FieldLayout, Kind, Scalar, Struct, StructLayout};

// ---------------------------------------------------------------------------------------
// Element layouts: what one element of each component looks like in memory.

contract_struct! {
    /// A pointer-and-count pair describing one scene component in simulated memory.
    ///
    /// `addr` is 0 and `count` is 0 when the component is absent (not built because the
    /// program does not reference it, or the scene has none).
    pub struct Component as "trax_component_t", prefix "COMPONENT" {
        /// Address of the first element.
        pub addr: u32,
        /// Number of elements.
        pub count: u32,
    }
}

contract_struct! {
    /// The camera, as stored in simulated memory (simtrax `.view` semantics).
    ///
    /// A primary ray through pixel `(x, y)` with image-plane coordinates
    /// `s = left + (right-left)*(x+0.5)/width`, `t = bottom + (top-bottom)*(y+0.5)/height`
    /// has origin `eye` and direction `normalize(distance*w + s*u + t*v)`, where `w` is the
    /// normalized gaze direction, `u` = normalize(gaze × up) (right) and `v` = u × w (up).
    pub struct Camera as "trax_camera_t", prefix "CAM" {
        /// Eye position.
        pub eye: [f32; 3],
        /// Right (unit).
        pub u: [f32; 3],
        /// Up (unit).
        pub v: [f32; 3],
        /// Gaze (unit).
        pub w: [f32; 3],
        /// Image-plane window: left edge.
        pub left: f32,
        /// Image-plane window: right edge.
        pub right: f32,
        /// Image-plane window: bottom edge.
        pub bottom: f32,
        /// Image-plane window: top edge.
        pub top: f32,
        /// Distance from the eye to the image plane.
        pub distance: f32,
        /// Lens aperture (0: pinhole).
        pub aperture: f32,
    }
}

contract_struct! {
    /// One framebuffer pixel: linear RGB.
    pub struct Pixel as "trax_pixel_t", prefix "PIXEL" {
        /// Red.
        pub r: f32,
        /// Green.
        pub g: f32,
        /// Blue.
        pub b: f32,
    }
}

contract_struct! {
    /// A BVH node. Interior node: `b == 0`, children at node indices `a` and `a + 1`.
    /// Leaf: `b` = triangle count (>= 1), triangles `a .. a + b`.
    pub struct BvhNode as "trax_bvh_node_t", prefix "BVH" {
        /// Minimum corner of the box.
        pub min: [f32; 3],
        /// Maximum corner of the box.
        pub max: [f32; 3],
        /// First child (interior) or first triangle (leaf).
        pub a: u32,
        /// 0 (interior) or the leaf's triangle count.
        pub b: u32,
    }
}

contract_struct! {
    /// A triangle: three vertices.
    pub struct Triangle as "trax_triangle_t", prefix "TRI" {
        /// First vertex.
        pub v0: [f32; 3],
        /// Second vertex.
        pub v1: [f32; 3],
        /// Third vertex.
        pub v2: [f32; 3],
    }
}

contract_struct! {
    /// Per-vertex normals of one triangle.
    pub struct VertexNormals as "trax_normals_t", prefix "NORMALS" {
        /// Normal at the first vertex.
        pub n0: [f32; 3],
        /// Normal at the second vertex.
        pub n1: [f32; 3],
        /// Normal at the third vertex.
        pub n2: [f32; 3],
    }
}

contract_struct! {
    /// Per-vertex texture coordinates of one triangle.
    pub struct TexCoords as "trax_texcoords_t", prefix "TEXCOORDS" {
        /// `(s, t)` at the first vertex.
        pub t0: [f32; 2],
        /// `(s, t)` at the second vertex.
        pub t1: [f32; 2],
        /// `(s, t)` at the third vertex.
        pub t2: [f32; 2],
    }
}

contract_struct! {
    /// A material.
    pub struct Material as "trax_material_t", prefix "MAT" {
        /// Diffuse reflectance (linear RGB).
        pub diffuse: [f32; 3],
        /// Specular reflectance (linear RGB).
        pub specular: [f32; 3],
        /// Emitted radiance (linear RGB).
        pub emission: [f32; 3],
        /// Phong exponent.
        pub shininess: f32,
        /// Flag bits (see the scene loader's `Material::flags`).
        pub flags: u32,
        /// Zero.
        pub reserved: u32,
    }
}

contract_struct! {
    /// A point light.
    pub struct PointLight as "trax_point_light_t", prefix "LIGHT" {
        /// Position.
        pub position: [f32; 3],
        /// Colour (intensity, linear RGB).
        pub color: [f32; 3],
    }
}

// ---------------------------------------------------------------------------------------
// The scene header and its components.

/// How the header refers to a component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// A `u32` address (one element; 0 when absent).
    Addr,
    /// A [`Component`]: address and element count.
    Range,
}

/// Where a component is placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    /// At the image builder's component alignment (64 bytes).
    Component,
    /// Also at the treelet alignment when treelets are aligned (e.g. to DRAM rows).
    Rows,
}

/// When a component is in the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Need {
    /// Always (camera, framebuffer).
    Always,
    /// Only when the program references its `__trax_scene_<name>` symbol.
    OnDemand,
}

/// What kernels may do to a component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Load only: a store faults.
    ReadOnly,
    /// Load and store.
    ReadWrite,
}

/// What a component has one element per: a bound of its length known before anything is
/// built, and whether it is built from the BVH.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Per {
    /// One element for the scene (the camera).
    Scene,
    /// One per pixel of the frame.
    Pixel,
    /// One per BVH node (a binary BVH over `n` triangles has fewer than `2n`); built from
    /// the BVH.
    Node,
    /// At most one per scene triangle (in BVH leaf order when a BVH is built).
    Triangle,
    /// One per triangle slot of the BVH's leaves; built from the BVH.
    LeafSlot,
    /// One per material.
    Material,
    /// One per point light.
    Light,
}

impl Per {
    /// Whether components of this kind are built from the BVH (the image builder builds
    /// one only when the program reads such a component).
    pub fn from_bvh(self) -> bool {
        matches!(self, Per::Node | Per::LeafSlot)
    }
}

/// One scene component: a header field naming an array of elements in memory.
#[derive(Clone, Copy, Debug)]
pub struct ComponentDesc {
    /// Header field name (also the suffix of its `__trax_scene_` symbol).
    pub name: &'static str,
    /// What one element is.
    pub element: Kind,
    /// Bytes per element.
    pub element_bytes: u32,
    /// How the header refers to it.
    pub slot: Slot,
    /// Placement alignment.
    pub align: Align,
    /// Always present or on demand.
    pub need: Need,
    /// Load only or load and store.
    pub access: Access,
    /// What it has one element per.
    pub per: Per,
    /// Byte offset of its field in the [`SceneHeader`].
    pub header_offset: u32,
    /// Doc comment (contents, element order).
    pub doc: &'static str,
    /// Reads the component's address and count from a header (count 1 for an [`Slot::Addr`]
    /// component that is present).
    pub get: fn(&SceneHeader) -> Component,
    /// Writes the component's address (and count, for [`Slot::Range`]) into a header.
    pub set: fn(&mut SceneHeader, Component),
}

/// A header slot: a `u32` address or a [`Component`].
pub trait HeaderSlot {
    /// The slot as an address and count.
    fn component(&self) -> Component;
    /// Stores an address and count into the slot.
    fn set_component(&mut self, c: Component);
}

impl HeaderSlot for u32 {
    fn component(&self) -> Component {
        Component {
            addr: *self,
            count: (*self != 0) as u32,
        }
    }
    fn set_component(&mut self, c: Component) {
        *self = c.addr;
    }
}

impl HeaderSlot for Component {
    fn component(&self) -> Component {
        *self
    }
    fn set_component(&mut self, c: Component) {
        *self = c;
    }
}

macro_rules! slot_type {
    (Addr) => {
        u32
    };
    (Range) => {
        Component
    };
}

/// Defines the scene header (scalar fields, then one field per component, then scalar
/// fields added later, which took reserved words so that no earlier field moved, then the
/// reserved words) and [`SCENE_COMPONENTS`] from one list: a component is one line.
macro_rules! scene_contract {
    (
        $(#[doc = $doc:literal])*
        pub struct $name:ident as $cname:literal, prefix $prefix:literal {
            $( $(#[doc = $sdoc:literal])* pub $s:ident : $sty:ty, )*
        }
        components {
            $( $(#[doc = $cdoc:literal])*
               $c:ident : $ety:ty => $slot:ident, $align:ident, $need:ident, $access:ident,
               per $per:ident; )*
        }
        tail {
            $( $(#[doc = $tdoc:literal])* pub $t:ident : $tty:ty, )*
        }
        $(#[doc = $rdoc:literal])* reserved: $nres:literal
    ) => {
        contract_struct! {
            $(#[doc = $doc])*
            pub struct $name as $cname, prefix $prefix {
                $( $(#[doc = $sdoc])* pub $s: $sty, )*
                $( $(#[doc = $cdoc])* pub $c: slot_type!($slot), )*
                $( $(#[doc = $tdoc])* pub $t: $tty, )*
                $(#[doc = $rdoc])* pub reserved: [u32; $nres],
            }
        }

        /// The scene components, in header order: the one list the image builder, the
        /// host runtime, `trax native`, `trax scene`, the prelude's `layout.rs` and the C
        /// header derive from.
        pub const SCENE_COMPONENTS: &[ComponentDesc] = &[$(
            ComponentDesc {
                name: stringify!($c),
                element: <$ety as Field>::KIND,
                element_bytes: std::mem::size_of::<$ety>() as u32,
                slot: Slot::$slot,
                align: Align::$align,
                need: Need::$need,
                access: Access::$access,
                per: Per::$per,
                header_offset: std::mem::offset_of!($name, $c) as u32,
                doc: concat!($($cdoc, "\n",)*),
                get: |h| HeaderSlot::component(&h.$c),
                set: |h, v| HeaderSlot::set_component(&mut h.$c, v),
            },
        )*];
    };
}

scene_contract! {
    /// The scene header at [`SCENE_HEADER_ADDR`]: image and rendering parameters, then one
    /// field per scene component ([`SCENE_COMPONENTS`]).
    ///
    /// All fields are 4-byte words, so the layout has no padding.
    pub struct SceneHeader as "trax_scene_header_t", prefix "HDR" {
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
    }
    components {
        /// The [`Camera`] (its address).
        camera: Camera => Addr, Component, Always, ReadOnly, per Scene;
        /// Framebuffer: `width*height` [`Pixel`]s, row 0 at the top.
        framebuffer: Pixel => Range, Component, Always, ReadWrite, per Pixel;
        /// [`BvhNode`]s, root at index 0; leaves index [`SceneHeader::triangles`].
        bvh_nodes: BvhNode => Range, Rows, OnDemand, ReadOnly, per Node;
        /// [`Triangle`]s, in BVH leaf order when the BVH is built.
        triangles: Triangle => Range, Rows, OnDemand, ReadOnly, per Triangle;
        /// Per-vertex normals ([`VertexNormals`]), same order as the triangles.
        normals: VertexNormals => Range, Component, OnDemand, ReadOnly, per Triangle;
        /// Per-vertex texture coordinates ([`TexCoords`]), same order as the triangles.
        texcoords: TexCoords => Range, Component, OnDemand, ReadOnly, per Triangle;
        /// Material index per triangle, same order as the triangles.
        material_ids: u32 => Range, Component, OnDemand, ReadOnly, per Triangle;
        /// [`Material`]s.
        materials: Material => Range, Component, OnDemand, ReadOnly, per Material;
        /// Indices of the emissive triangles, for light sampling.
        emitters: u32 => Range, Component, OnDemand, ReadOnly, per Triangle;
        /// [`PointLight`]s.
        point_lights: PointLight => Range, Component, OnDemand, ReadOnly, per Light;
        /// BVH parent pointers: the parent's node index per node (the root's is 0xFFFFFFFF).
        bvh_parents: u32 => Range, Component, OnDemand, ReadOnly, per Node;
        /// Treelet id per BVH node.
        treelet_ids: u32 => Range, Component, OnDemand, ReadOnly, per Node;
        /// Triangle treelet id per triangle slot.
        /// (Ids follow the node treelets', as the assembler's `Treelets` numbers them;
        /// 0xFFFFFFFF for padding slots.)
        tri_treelet_ids: u32 => Range, Component, OnDemand, ReadOnly, per LeafSlot;
        /// BVH leaf (node index) per triangle slot.
        /// (A leaf's triangles are the run of slots from its first that name it;
        /// 0xFFFFFFFF for padding slots.)
        tri_leaf_ids: u32 => Range, Component, OnDemand, ReadOnly, per LeafSlot;
    }
    tail {
        /// Rays the chip's ray stream memory holds (0: the chip has none).
        pub stream_rays: u32,
        /// Bytes of one ray record in the stream memory.
        pub stream_ray_bytes: u32,
        /// Ray buffers of the stream memory (stream ids `0..stream_buffers`).
        pub stream_buffers: u32,
        /// The `trax.setpipe` modes the chip's TMs offer, bit `m` for mode `m`.
        /// (Bit 0, general-purpose units, always; 0b111 with both pipelines.)
        pub pipe_modes: u32,
    }
    /// Reserved for future components; zero.
    reserved: 1
}

impl SceneHeader {
    /// A header for a `width` x `height` image: [`SCENE_MAGIC`], [`SCENE_VERSION`], the
    /// size and its reciprocals set, every other field zero (components absent). Callers
    /// set the rest with struct update syntax.
    pub fn new(width: u32, height: u32) -> SceneHeader {
        SceneHeader {
            magic: SCENE_MAGIC,
            version: SCENE_VERSION,
            width,
            height,
            inv_width: 1.0 / width as f32,
            inv_height: 1.0 / height as f32,
            ..SceneHeader::default()
        }
    }
}

/// Size of [`SceneHeader`] in bytes.
pub const SCENE_HEADER_SIZE: usize = std::mem::size_of::<SceneHeader>();
/// Bytes of one framebuffer [`Pixel`].
pub const PIXEL_BYTES: u32 = std::mem::size_of::<Pixel>() as u32;

/// The component called `name`.
pub fn component(name: &str) -> Option<&'static ComponentDesc> {
    SCENE_COMPONENTS.iter().find(|c| c.name == name)
}

/// Byte offset of each header field, by name, for tools that lay out or check memory.
pub fn scene_header_fields() -> Vec<(&'static str, usize)> {
    SceneHeader::layout()
        .fields
        .iter()
        .map(|f| (f.name, f.offset))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    /// Every contract struct, for the checks below.
    fn layouts() -> Vec<StructLayout> {
        vec![
            SceneHeader::layout(),
            Component::layout(),
            Camera::layout(),
            Pixel::layout(),
            BvhNode::layout(),
            Triangle::layout(),
            VertexNormals::layout(),
            TexCoords::layout(),
            Material::layout(),
            PointLight::layout(),
        ]
    }

    #[test]
    fn layouts_tile_their_structs() {
        for l in layouts() {
            let mut at = 0;
            for f in &l.fields {
                assert_eq!(f.offset, at, "{}.{}", l.name, f.name);
                assert_eq!(f.size % 4, 0, "{}.{}", l.name, f.name);
                at += f.size;
            }
            assert_eq!(at, l.size, "{}", l.name);
        }
        assert_eq!(SceneHeader::layout().size, SCENE_HEADER_SIZE);
        // The element sizes kernels and tools were built against (an ABI change must
        // change this table, `SCENE_VERSION` and the prelude's `layout.rs` together).
        let sizes: Vec<(&str, u32)> = SCENE_COMPONENTS
            .iter()
            .map(|c| (c.name, c.element_bytes))
            .collect();
        let pinned = [
            ("camera", 72),
            ("framebuffer", 12),
            ("bvh_nodes", 32),
            ("triangles", 36),
            ("normals", 36),
            ("texcoords", 24),
            ("material_ids", 4),
            ("materials", 48),
            ("emitters", 4),
            ("point_lights", 24),
            ("bvh_parents", 4),
            ("treelet_ids", 4),
            ("tri_treelet_ids", 4),
            ("tri_leaf_ids", 4),
        ];
        assert_eq!(sizes, pinned);
    }

    /// A value whose every word differs (word `k` is `base + k`), built through the
    /// decoder, so encoding it back must give the same bytes at the `repr(C)` offsets.
    fn distinct<T: Field>(base: u32) -> (T, Vec<u8>) {
        let bytes: Vec<u8> = (0..size_of::<T>() as u32 / 4)
            .flat_map(|k| (base + k).to_le_bytes())
            .collect();
        (decode::<T>(&bytes).unwrap(), bytes)
    }

    #[test]
    fn encoding_is_the_repr_c_layout() {
        let (h, bytes) = distinct::<SceneHeader>(1000);
        assert_eq!(h.to_bytes(), bytes);
        let word = |off: usize| 1000 + off as u32 / 4;
        assert_eq!(h.magic, word(offset_of!(SceneHeader, magic)));
        assert_eq!(h.seed, word(offset_of!(SceneHeader, seed)));
        assert_eq!(h.camera, word(offset_of!(SceneHeader, camera)));
        assert_eq!(
            h.framebuffer.count,
            word(offset_of!(SceneHeader, framebuffer) + 4)
        );
        assert_eq!(
            h.treelet_ids.addr,
            word(offset_of!(SceneHeader, treelet_ids))
        );
        assert_eq!(h.reserved[0], word(offset_of!(SceneHeader, reserved)));
        assert_eq!(
            h.stream_buffers,
            word(offset_of!(SceneHeader, stream_buffers))
        );
        let (c, bytes) = distinct::<Camera>(0x4000_0000);
        assert_eq!(c.to_bytes(), bytes);
        assert_eq!(
            c.right.to_bits(),
            0x4000_0000 + offset_of!(Camera, right) as u32 / 4
        );
        let (m, bytes) = distinct::<Material>(7);
        assert_eq!(m.to_bytes(), bytes);
        assert_eq!(m.flags, 7 + offset_of!(Material, flags) as u32 / 4);
        let (n, bytes) = distinct::<BvhNode>(9);
        assert_eq!(encode([n, n]), [bytes.clone(), bytes].concat());
        assert_eq!(decode::<BvhNode>(&[0; 31]), None);
    }

    #[test]
    fn the_component_table_is_the_header() {
        let l = SceneHeader::layout();
        for c in SCENE_COMPONENTS {
            let f = l.field(c.name).unwrap();
            assert_eq!(f.offset as u32, c.header_offset, "{}", c.name);
            let slot = match c.slot {
                Slot::Addr => 4,
                Slot::Range => size_of::<Component>(),
            };
            assert_eq!(f.size, slot, "{}", c.name);
            assert!(
                c.element_bytes % 4 == 0 && c.element_bytes > 0,
                "{}",
                c.name
            );
            // get and set address the component's own field.
            let mut h = SceneHeader::default();
            (c.set)(
                &mut h,
                Component {
                    addr: 0x40,
                    count: 3,
                },
            );
            let b = h.to_bytes();
            let off = c.header_offset as usize;
            assert_eq!(u32::get(&b[off..]), 0x40, "{}", c.name);
            let nonzero = b.iter().filter(|&&x| x != 0).count();
            assert_eq!(
                nonzero,
                if c.slot == Slot::Range { 2 } else { 1 },
                "{}",
                c.name
            );
            let back = (c.get)(&h);
            assert_eq!(back.addr, 0x40);
            assert_eq!(back.count, if c.slot == Slot::Range { 3 } else { 1 });
        }
        // Every header field after the scalars is a component, up to the tail scalars.
        let first = l.field("camera").unwrap().offset;
        let tail = l.field("stream_rays").unwrap().offset;
        let comps: Vec<&str> = l
            .fields
            .iter()
            .filter(|f| f.offset >= first && f.offset < tail)
            .map(|f| f.name)
            .collect();
        let table: Vec<&str> = SCENE_COMPONENTS.iter().map(|c| c.name).collect();
        assert_eq!(comps, table);
        assert_eq!(component("framebuffer").unwrap().access, Access::ReadWrite);
        assert_eq!(scene_header_fields().len(), l.fields.len());
    }

    // The memory regions do not overlap (checked at compile time).
    const _: () = assert!(NULL_GUARD_END <= SCENE_HEADER_ADDR);
    const _: () = assert!(SCENE_HEADER_ADDR as usize + SCENE_HEADER_SIZE <= TEXT_BASE as usize);
    const _: () = assert!(TEXT_BASE < STACK_TOP - DEFAULT_STACK_SIZE);
}
