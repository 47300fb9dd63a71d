//! Byte layouts of the scene data in simulated memory, generated from the scene
//! contract (`trax_runtime::abi`) by `trax_runtime::prelude::render_layout`: do not
//! edit; after changing the contract run
//! `TRAX_BLESS=1 cargo test -p trax-runtime --lib prelude` to rewrite this file.
//!
//! Header offsets are used by the host implementation only (on TRaX the linker
//! resolves `__trax_scene_<field>` symbols).

/// Address of the scene header.
pub const SCENE_HEADER_ADDR: u32 = 0x10000;
/// Value of the header's `magic` field ("TRAX").
pub const SCENE_MAGIC: u32 = 0x58415254;
/// Value of the header's `version` field.
pub const SCENE_VERSION: u32 = 3;
/// The global register `pixel_share` hands pixels out from (sampled simulation
/// follows a frame's progress along it).
pub const PIXEL_COUNTER_REG: u32 = 255;
/// The global registers `declare_work` records a kernel's work counter in (its
/// register plus one; 0: none declared) and the items it hands out.
pub const WORK_COUNTER_REG: u32 = 254;
pub const WORK_ITEMS_REG: u32 = 253;
/// Words of the ray record `trax::stream` writes and reads (thesis §3.2.1).
pub const STREAM_RECORD_WORDS: usize = 12;

// `abi::SceneHeader` (C: `trax_scene_header_t`).
/// `SCENE_MAGIC`.
pub const HDR_MAGIC: u32 = 0;
/// `SCENE_VERSION`.
pub const HDR_VERSION: u32 = 4;
/// Image width in pixels.
pub const HDR_WIDTH: u32 = 8;
/// Image height in pixels.
pub const HDR_HEIGHT: u32 = 12;
/// `1.0 / width`.
pub const HDR_INV_WIDTH: u32 = 16;
/// `1.0 / height`.
pub const HDR_INV_HEIGHT: u32 = 20;
/// Samples per pixel requested on the command line.
pub const HDR_SPP: u32 = 24;
/// Maximum path depth requested on the command line.
pub const HDR_MAX_DEPTH: u32 = 28;
/// Ray offset epsilon, scaled to the scene.
pub const HDR_EPSILON: u32 = 32;
/// Seed for per-thread random streams.
pub const HDR_SEED: u32 = 36;
/// Background (sky) colour, linear RGB.
pub const HDR_BACKGROUND: u32 = 40;
/// The `Camera` (its address).
pub const HDR_CAMERA: u32 = 52;
/// Framebuffer: `width*height` `Pixel`s, row 0 at the top.
pub const HDR_FRAMEBUFFER: u32 = 56;
/// `BvhNode`s, root at index 0; leaves index `SceneHeader::triangles`.
pub const HDR_BVH_NODES: u32 = 64;
/// `Triangle`s, in BVH leaf order when the BVH is built.
pub const HDR_TRIANGLES: u32 = 72;
/// Per-vertex normals (`VertexNormals`), same order as the triangles.
pub const HDR_NORMALS: u32 = 80;
/// Per-vertex texture coordinates (`TexCoords`), same order as the triangles.
pub const HDR_TEXCOORDS: u32 = 88;
/// Material index per triangle, same order as the triangles.
pub const HDR_MATERIAL_IDS: u32 = 96;
/// `Material`s.
pub const HDR_MATERIALS: u32 = 104;
/// Indices of the emissive triangles, for light sampling.
pub const HDR_EMITTERS: u32 = 112;
/// `PointLight`s.
pub const HDR_POINT_LIGHTS: u32 = 120;
/// BVH parent pointers: the parent's node index per node (the root's is 0xFFFFFFFF).
pub const HDR_BVH_PARENTS: u32 = 128;
/// Treelet id per BVH node.
pub const HDR_TREELET_IDS: u32 = 136;
/// Triangle treelet id per triangle slot.
pub const HDR_TRI_TREELET_IDS: u32 = 144;
/// BVH leaf (node index) per triangle slot.
pub const HDR_TRI_LEAF_IDS: u32 = 152;
/// Rays the chip's ray stream memory holds (0: the chip has none).
pub const HDR_STREAM_RAYS: u32 = 160;
/// Bytes of one ray record in the stream memory.
pub const HDR_STREAM_RAY_BYTES: u32 = 164;
/// Ray buffers of the stream memory (stream ids `0..stream_buffers`).
pub const HDR_STREAM_BUFFERS: u32 = 168;
/// The `trax.setpipe` modes the chip's TMs offer, bit `m` for mode `m`.
pub const HDR_PIPE_MODES: u32 = 172;
/// Reserved for future components; zero.
pub const HDR_RESERVED: u32 = 176;
/// Size of `SceneHeader` in bytes.
pub const HDR_SIZE: u32 = 180;

// `abi::Component` (C: `trax_component_t`).
/// Address of the first element.
pub const COMPONENT_ADDR: u32 = 0;
/// Number of elements.
pub const COMPONENT_COUNT: u32 = 4;
/// Size of `Component` in bytes.
pub const COMPONENT_SIZE: u32 = 8;

// `abi::Camera` (C: `trax_camera_t`).
/// Eye position.
pub const CAM_EYE: u32 = 0;
/// Right (unit).
pub const CAM_U: u32 = 12;
/// Up (unit).
pub const CAM_V: u32 = 24;
/// Gaze (unit).
pub const CAM_W: u32 = 36;
/// Image-plane window: left edge.
pub const CAM_LEFT: u32 = 48;
/// Image-plane window: right edge.
pub const CAM_RIGHT: u32 = 52;
/// Image-plane window: bottom edge.
pub const CAM_BOTTOM: u32 = 56;
/// Image-plane window: top edge.
pub const CAM_TOP: u32 = 60;
/// Distance from the eye to the image plane.
pub const CAM_DISTANCE: u32 = 64;
/// Lens aperture (0: pinhole).
pub const CAM_APERTURE: u32 = 68;
/// Size of `Camera` in bytes.
pub const CAM_SIZE: u32 = 72;

// `abi::Pixel` (C: `trax_pixel_t`).
/// Red.
pub const PIXEL_R: u32 = 0;
/// Green.
pub const PIXEL_G: u32 = 4;
/// Blue.
pub const PIXEL_B: u32 = 8;
/// Size of `Pixel` in bytes.
pub const PIXEL_SIZE: u32 = 12;

// `abi::BvhNode` (C: `trax_bvh_node_t`).
/// Minimum corner of the box.
pub const BVH_MIN: u32 = 0;
/// Maximum corner of the box.
pub const BVH_MAX: u32 = 12;
/// First child (interior) or first triangle (leaf).
pub const BVH_A: u32 = 24;
/// 0 (interior) or the leaf's triangle count.
pub const BVH_B: u32 = 28;
/// Size of `BvhNode` in bytes.
pub const BVH_SIZE: u32 = 32;

// `abi::Triangle` (C: `trax_triangle_t`).
/// First vertex.
pub const TRI_V0: u32 = 0;
/// Second vertex.
pub const TRI_V1: u32 = 12;
/// Third vertex.
pub const TRI_V2: u32 = 24;
/// Size of `Triangle` in bytes.
pub const TRI_SIZE: u32 = 36;

// `abi::VertexNormals` (C: `trax_normals_t`).
/// Normal at the first vertex.
pub const NORMALS_N0: u32 = 0;
/// Normal at the second vertex.
pub const NORMALS_N1: u32 = 12;
/// Normal at the third vertex.
pub const NORMALS_N2: u32 = 24;
/// Size of `VertexNormals` in bytes.
pub const NORMALS_SIZE: u32 = 36;

// `abi::TexCoords` (C: `trax_texcoords_t`).
/// `(s, t)` at the first vertex.
pub const TEXCOORDS_T0: u32 = 0;
/// `(s, t)` at the second vertex.
pub const TEXCOORDS_T1: u32 = 8;
/// `(s, t)` at the third vertex.
pub const TEXCOORDS_T2: u32 = 16;
/// Size of `TexCoords` in bytes.
pub const TEXCOORDS_SIZE: u32 = 24;

// `abi::Material` (C: `trax_material_t`).
/// Diffuse reflectance (linear RGB).
pub const MAT_DIFFUSE: u32 = 0;
/// Specular reflectance (linear RGB).
pub const MAT_SPECULAR: u32 = 12;
/// Emitted radiance (linear RGB).
pub const MAT_EMISSION: u32 = 24;
/// Phong exponent.
pub const MAT_SHININESS: u32 = 36;
/// Flag bits (see the scene loader's `Material::flags`).
pub const MAT_FLAGS: u32 = 40;
/// Zero.
pub const MAT_RESERVED: u32 = 44;
/// Size of `Material` in bytes.
pub const MAT_SIZE: u32 = 48;

// `abi::PointLight` (C: `trax_point_light_t`).
/// Position.
pub const LIGHT_POSITION: u32 = 0;
/// Colour (intensity, linear RGB).
pub const LIGHT_COLOR: u32 = 12;
/// Size of `PointLight` in bytes.
pub const LIGHT_SIZE: u32 = 24;

// Bytes per element of each component.
/// `camera`: Camera.
pub const CAMERA_STRIDE: u32 = 72;
/// `framebuffer`: Pixel.
pub const FRAMEBUFFER_STRIDE: u32 = 12;
/// `bvh_nodes`: BvhNode.
pub const BVH_NODES_STRIDE: u32 = 32;
/// `triangles`: Triangle.
pub const TRIANGLES_STRIDE: u32 = 36;
/// `normals`: VertexNormals.
pub const NORMALS_STRIDE: u32 = 36;
/// `texcoords`: TexCoords.
pub const TEXCOORDS_STRIDE: u32 = 24;
/// `material_ids`: u32.
pub const MATERIAL_IDS_STRIDE: u32 = 4;
/// `materials`: Material.
pub const MATERIALS_STRIDE: u32 = 48;
/// `emitters`: u32.
pub const EMITTERS_STRIDE: u32 = 4;
/// `point_lights`: PointLight.
pub const POINT_LIGHTS_STRIDE: u32 = 24;
/// `bvh_parents`: u32.
pub const BVH_PARENTS_STRIDE: u32 = 4;
/// `treelet_ids`: u32.
pub const TREELET_IDS_STRIDE: u32 = 4;
/// `tri_treelet_ids`: u32.
pub const TRI_TREELET_IDS_STRIDE: u32 = 4;
/// `tri_leaf_ids`: u32.
pub const TRI_LEAF_IDS_STRIDE: u32 = 4;
