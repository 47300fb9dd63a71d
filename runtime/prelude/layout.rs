//! Byte layouts of the scene data in simulated memory (see the runtime's `abi.rs`).
//!
//! Header offsets are used by the host implementation only (on TRaX the linker resolves
//! `__trax_scene_<field>` symbols); a host test checks every one against
//! `abi::SceneHeader` with `offset_of!`.

/// Address of the scene header.
pub const SCENE_HEADER_ADDR: u32 = 0x0001_0000;

/// Header field offsets, in `abi::SceneHeader` order.
pub const HDR_MAGIC: u32 = 0;
pub const HDR_VERSION: u32 = 4;
pub const HDR_WIDTH: u32 = 8;
pub const HDR_HEIGHT: u32 = 12;
pub const HDR_INV_WIDTH: u32 = 16;
pub const HDR_INV_HEIGHT: u32 = 20;
pub const HDR_SPP: u32 = 24;
pub const HDR_MAX_DEPTH: u32 = 28;
pub const HDR_EPSILON: u32 = 32;
pub const HDR_SEED: u32 = 36;
pub const HDR_BACKGROUND: u32 = 40;
pub const HDR_CAMERA: u32 = 52;
pub const HDR_FRAMEBUFFER: u32 = 56;
pub const HDR_BVH_NODES: u32 = 64;
pub const HDR_TRIANGLES: u32 = 72;
pub const HDR_NORMALS: u32 = 80;
pub const HDR_TEXCOORDS: u32 = 88;
pub const HDR_MATERIAL_IDS: u32 = 96;
pub const HDR_MATERIALS: u32 = 104;
pub const HDR_EMITTERS: u32 = 112;
pub const HDR_POINT_LIGHTS: u32 = 120;
pub const HDR_BVH_PARENTS: u32 = 128;
pub const HDR_TREELET_IDS: u32 = 136;
pub const HDR_RESERVED: u32 = 144;
/// Size of the header in bytes.
pub const HDR_SIZE: u32 = 176;

/// Offsets inside a component (`abi::Component`): element address, element count.
pub const COMPONENT_ADDR: u32 = 0;
pub const COMPONENT_COUNT: u32 = 4;

/// Offsets inside the camera (`abi::Camera`).
pub const CAM_EYE: u32 = 0;
pub const CAM_U: u32 = 12;
pub const CAM_V: u32 = 24;
pub const CAM_W: u32 = 36;
pub const CAM_LEFT: u32 = 48;
pub const CAM_RIGHT: u32 = 52;
pub const CAM_BOTTOM: u32 = 56;
pub const CAM_TOP: u32 = 60;
pub const CAM_DISTANCE: u32 = 64;
pub const CAM_APERTURE: u32 = 68;
/// Size of the camera in bytes.
pub const CAM_SIZE: u32 = 72;

/// Bytes per framebuffer pixel (3 × f32).
pub const PIXEL_SIZE: u32 = 12;
/// Bytes per BVH node: min (3 × f32), max (3 × f32), a (u32), b (u32).
pub const BVH_NODE_SIZE: u32 = 32;
pub const BVH_MIN: u32 = 0;
pub const BVH_MAX: u32 = 12;
pub const BVH_A: u32 = 24;
pub const BVH_B: u32 = 28;
/// Bytes per triangle: three vertices of 3 × f32.
pub const TRIANGLE_SIZE: u32 = 36;
/// Bytes per triangle of per-vertex normals (3 × 3 × f32).
pub const NORMALS_SIZE: u32 = 36;
/// Bytes per triangle of per-vertex texture coordinates (3 × 2 × f32).
pub const TEXCOORDS_SIZE: u32 = 24;
/// Bytes per material: diffuse, specular, emission (3 × f32 each), shininess (f32),
/// flags (u32), reserved (u32).
pub const MATERIAL_SIZE: u32 = 48;
pub const MAT_DIFFUSE: u32 = 0;
pub const MAT_SPECULAR: u32 = 12;
pub const MAT_EMISSION: u32 = 24;
pub const MAT_SHININESS: u32 = 36;
pub const MAT_FLAGS: u32 = 40;
/// Bytes per point light: position (3 × f32), colour (3 × f32).
pub const POINT_LIGHT_SIZE: u32 = 24;
pub const LIGHT_POSITION: u32 = 0;
pub const LIGHT_COLOR: u32 = 12;
