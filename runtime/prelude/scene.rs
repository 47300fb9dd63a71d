//! Scene access: header fields, triangles, materials, lights, BVH nodes and the
//! framebuffer, read from simulated memory (layouts in `layout.rs`).

use super::hw;
use super::layout;
use super::math::Vec3;

/// Reads a `Vec3` stored as three consecutive f32 at `addr`.
pub fn load_vec3(addr: u32) -> Vec3 {
    Vec3::new(
        hw::load_f32(addr),
        hw::load_f32(addr + 4),
        hw::load_f32(addr + 8),
    )
}

/// Writes a `Vec3` as three consecutive f32 at `addr`.
pub fn store_vec3(addr: u32, v: Vec3) {
    hw::store_f32(addr, v.x);
    hw::store_f32(addr + 4, v.y);
    hw::store_f32(addr + 8, v.z);
}

// ---- Header scalars ----

/// Image width in pixels.
pub fn width() -> u32 {
    hw::load_u32(hw::hdr_width())
}

/// Image height in pixels.
pub fn height() -> u32 {
    hw::load_u32(hw::hdr_height())
}

/// `1 / width`.
pub fn inv_width() -> f32 {
    hw::load_f32(hw::hdr_inv_width())
}

/// `1 / height`.
pub fn inv_height() -> f32 {
    hw::load_f32(hw::hdr_inv_height())
}

/// Samples per pixel.
pub fn spp() -> u32 {
    hw::load_u32(hw::hdr_spp())
}

/// Maximum path depth.
pub fn max_depth() -> u32 {
    hw::load_u32(hw::hdr_max_depth())
}

/// Ray offset epsilon.
pub fn epsilon() -> f32 {
    hw::load_f32(hw::hdr_epsilon())
}

/// Seed of the random streams.
pub fn seed() -> u32 {
    hw::load_u32(hw::hdr_seed())
}

/// Background colour.
pub fn background() -> Vec3 {
    load_vec3(hw::hdr_background())
}

/// True if the header carries the expected magic and version.
pub fn header_is_valid() -> bool {
    hw::load_u32(hw::hdr_magic()) == layout::SCENE_MAGIC
        && hw::load_u32(hw::hdr_version()) == layout::SCENE_VERSION
}

/// Address of the camera.
pub fn camera_addr() -> u32 {
    hw::load_u32(hw::hdr_camera())
}

// ---- Framebuffer ----

/// Address of pixel `(x, y)`; row 0 is the top of the image.
pub fn pixel_addr(x: u32, y: u32) -> u32 {
    let fb = hw::load_u32(hw::hdr_framebuffer() + layout::COMPONENT_ADDR);
    fb + (y * width() + x) * layout::FRAMEBUFFER_STRIDE
}

/// Writes pixel `(x, y)` (linear RGB; row 0 is the top of the image).
pub fn set_pixel(x: u32, y: u32, c: Vec3) {
    store_vec3(pixel_addr(x, y), c);
}

/// Writes pixel number `i` (`y * width + x`).
pub fn set_pixel_index(i: u32, c: Vec3) {
    let fb = hw::load_u32(hw::hdr_framebuffer() + layout::COMPONENT_ADDR);
    store_vec3(fb + i * layout::FRAMEBUFFER_STRIDE, c);
}

/// What [`PixelShare::next_pixel`] returns when every pixel has been handed out.
pub const NO_PIXEL: u32 = 0xffff_ffff;

/// The global register that counts the pixels [`pixel_share`] has handed out (from the
/// scene contract). A kernel that calls `pixel_share` must leave it alone.
pub const PIXEL_COUNTER_REG: u32 = layout::PIXEL_COUNTER_REG;

/// Pixels handed out per `atomic_add` on [`PIXEL_COUNTER_REG`]. One: the atomic costs a
/// thread one quantum per pixel, little beside a path-tracer or AO pixel, while the last
/// blocks decide how long the other threads sit idle at the end (path tracer on the 100k
/// dragon, 16 baseline TMs: 16% of thread-cycles idle with blocks of 1, 36% with blocks of
/// 4).
pub const PIXEL_BLOCK: u32 = 1;

/// A thread's dynamic share of the image's pixels: each thread takes the next
/// [`PIXEL_BLOCK`] pixels from a chip-wide counter (`trax::atomic_add` on
/// [`PIXEL_COUNTER_REG`]) whenever it is done with its last ones, so threads that draw
/// cheap pixels (background) take more of them and none sits idle while others still have
/// a long static share to do. Which thread renders which pixel then depends on the chip
/// and on timing: seed each sample's random stream with `trax::seed_pixel` so that the
/// image does not.
pub struct PixelShare {
    /// Next pixel of the current block.
    next: u32,
    /// One past the current block's last pixel.
    end: u32,
    pixels: u32,
    done: bool,
}

impl PixelShare {
    /// The next pixel number (`y * width + x`) for this thread, or [`NO_PIXEL`] once every
    /// pixel has been handed out.
    pub fn next_pixel(&mut self) -> u32 {
        if self.next == self.end {
            if self.done {
                return NO_PIXEL;
            }
            let first = hw::atomic_add(PIXEL_COUNTER_REG, PIXEL_BLOCK);
            if first >= self.pixels {
                self.done = true;
                return NO_PIXEL;
            }
            self.next = first;
            self.end = if self.pixels - first < PIXEL_BLOCK {
                self.pixels
            } else {
                first + PIXEL_BLOCK
            };
        }
        let i = self.next;
        self.next += 1;
        i
    }
}

/// The calling thread's dynamic share of the image's pixels (one pass over the image per
/// run: the counter is never reset).
pub fn pixel_share() -> PixelShare {
    PixelShare {
        next: 0,
        end: 0,
        pixels: width() * height(),
        done: false,
    }
}

/// Reads pixel `(x, y)`.
pub fn get_pixel(x: u32, y: u32) -> Vec3 {
    load_vec3(pixel_addr(x, y))
}

// ---- Triangles ----

/// A triangle's three vertices.
#[derive(Clone, Copy)]
pub struct Triangle {
    pub v0: Vec3,
    pub v1: Vec3,
    pub v2: Vec3,
}

impl Triangle {
    /// Unnormalised geometric normal `(v1 - v0) × (v2 - v0)`.
    pub fn normal_unnormalized(&self) -> Vec3 {
        (self.v1 - self.v0).cross(self.v2 - self.v0)
    }

    /// Unit geometric normal, the same direction at every scale: when the cross product of
    /// the edges (or its squared length) overflows or underflows, the edges are first
    /// multiplied by a power of two ([`super::math::pow2_scale`], exact). Bit for bit
    /// `normal_unnormalized().normalize()` wherever no rescaling is needed.
    pub fn normal(&self) -> Vec3 {
        let e1 = self.v1 - self.v0;
        let e2 = self.v2 - self.v0;
        let n = e1.cross(e2);
        let d = n.dot(n);
        if super::math::in_range(d) {
            return n.scale(super::invsqrt(d));
        }
        let k = super::math::pow2_scale(super::max(e1.max_abs(), e2.max_abs()));
        e1.scale(k).cross(e2.scale(k)).normalize()
    }

    /// Area (overflows for edges beyond about 1e19; see [`Triangle::area_scaled`]).
    pub fn area(&self) -> f32 {
        0.5 * self.normal_unnormalized().length()
    }

    /// Area times `k²`, the edges multiplied by `k` first: with `k` a power of two that
    /// brings a length of the scene to about 1 ([`super::math::pow2_scale`]), the area in
    /// that length's units, finite where the plain area overflows.
    pub fn area_scaled(&self, k: f32) -> f32 {
        0.5 * (self.v1 - self.v0)
            .scale(k)
            .cross((self.v2 - self.v0).scale(k))
            .length()
    }

    /// The point with barycentric coordinates `(1 - u - v, u, v)`.
    pub fn point(&self, u: f32, v: f32) -> Vec3 {
        self.v0.scale(1.0 - u - v) + self.v1.scale(u) + self.v2.scale(v)
    }
}

/// Number of triangles.
pub fn triangle_count() -> u32 {
    hw::load_u32(hw::hdr_triangles() + layout::COMPONENT_COUNT)
}

/// Address of triangle 0.
pub fn triangles_base() -> u32 {
    hw::load_u32(hw::hdr_triangles() + layout::COMPONENT_ADDR)
}

/// Triangle `i`.
pub fn triangle(i: u32) -> Triangle {
    triangle_at(triangles_base(), i)
}

/// Triangle `i` of the array at `base` (see [`triangles_base`]): in a loop, the header is
/// read once.
pub fn triangle_at(base: u32, i: u32) -> Triangle {
    triangle_stored(base + i * layout::TRIANGLES_STRIDE)
}

/// The triangle stored at address `a`.
pub fn triangle_stored(a: u32) -> Triangle {
    Triangle {
        v0: load_vec3(a),
        v1: load_vec3(a + layout::TRI_V1),
        v2: load_vec3(a + layout::TRI_V2),
    }
}

/// Number of triangles with per-vertex normals (0 if the scene has none).
pub fn normals_count() -> u32 {
    hw::load_u32(hw::hdr_normals() + layout::COMPONENT_COUNT)
}

/// Interpolated shading normal of triangle `i` at barycentrics `(u, v)`, normalised.
pub fn shading_normal(i: u32, u: f32, v: f32) -> Vec3 {
    let a = hw::load_u32(hw::hdr_normals() + layout::COMPONENT_ADDR) + i * layout::NORMALS_STRIDE;
    let n0 = load_vec3(a);
    let n1 = load_vec3(a + layout::NORMALS_N1);
    let n2 = load_vec3(a + layout::NORMALS_N2);
    (n0.scale(1.0 - u - v) + n1.scale(u) + n2.scale(v)).normalize()
}

// ---- Materials ----

/// A material.
#[derive(Clone, Copy)]
pub struct Material {
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub emission: Vec3,
    pub shininess: f32,
    pub flags: u32,
}

/// Material index of triangle `i` (0 if the scene has no material ids).
pub fn material_id(i: u32) -> u32 {
    let c = hw::hdr_material_ids();
    if hw::load_u32(c + layout::COMPONENT_COUNT) == 0 {
        return 0;
    }
    hw::load_u32(hw::load_u32(c + layout::COMPONENT_ADDR) + i * layout::MATERIAL_IDS_STRIDE)
}

/// Number of materials.
pub fn material_count() -> u32 {
    hw::load_u32(hw::hdr_materials() + layout::COMPONENT_COUNT)
}

/// Material `m`; a grey diffuse default if the scene has no materials.
pub fn material(m: u32) -> Material {
    let c = hw::hdr_materials();
    if hw::load_u32(c + layout::COMPONENT_COUNT) == 0 {
        return Material {
            diffuse: Vec3::splat(0.7),
            specular: Vec3::zero(),
            emission: Vec3::zero(),
            shininess: 0.0,
            flags: 0,
        };
    }
    let a = hw::load_u32(c + layout::COMPONENT_ADDR) + m * layout::MATERIALS_STRIDE;
    Material {
        diffuse: load_vec3(a + layout::MAT_DIFFUSE),
        specular: load_vec3(a + layout::MAT_SPECULAR),
        emission: load_vec3(a + layout::MAT_EMISSION),
        shininess: hw::load_f32(a + layout::MAT_SHININESS),
        flags: hw::load_u32(a + layout::MAT_FLAGS),
    }
}

/// Material of triangle `i`.
pub fn triangle_material(i: u32) -> Material {
    material(material_id(i))
}

// ---- Lights ----

/// Number of emissive triangles.
pub fn emitter_count() -> u32 {
    hw::load_u32(hw::hdr_emitters() + layout::COMPONENT_COUNT)
}

/// Triangle index of emitter `k`.
pub fn emitter(k: u32) -> u32 {
    hw::load_u32(
        hw::load_u32(hw::hdr_emitters() + layout::COMPONENT_ADDR) + k * layout::EMITTERS_STRIDE,
    )
}

/// A point light.
#[derive(Clone, Copy)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
}

/// Number of point lights.
pub fn point_light_count() -> u32 {
    hw::load_u32(hw::hdr_point_lights() + layout::COMPONENT_COUNT)
}

/// Point light `k`.
pub fn point_light(k: u32) -> PointLight {
    let a = hw::load_u32(hw::hdr_point_lights() + layout::COMPONENT_ADDR)
        + k * layout::POINT_LIGHTS_STRIDE;
    PointLight {
        position: load_vec3(a + layout::LIGHT_POSITION),
        color: load_vec3(a + layout::LIGHT_COLOR),
    }
}

// ---- BVH ----

/// A BVH node. Interior: `b == 0`, children `a` and `a + 1`. Leaf: triangles
/// `a .. a + b`.
#[derive(Clone, Copy)]
pub struct BvhNode {
    pub min: Vec3,
    pub max: Vec3,
    pub a: u32,
    pub b: u32,
}

impl BvhNode {
    /// True for a leaf.
    pub fn is_leaf(&self) -> bool {
        self.b != 0
    }
}

/// Number of BVH nodes.
pub fn bvh_node_count() -> u32 {
    hw::load_u32(hw::hdr_bvh_nodes() + layout::COMPONENT_COUNT)
}

/// Address of BVH node 0 (0 if the scene has no BVH).
pub fn bvh_base() -> u32 {
    hw::load_u32(hw::hdr_bvh_nodes() + layout::COMPONENT_ADDR)
}

/// BVH node `i` of the tree at `base` (see [`bvh_base`]).
pub fn bvh_node_at(base: u32, i: u32) -> BvhNode {
    let a = base + i * layout::BVH_NODES_STRIDE;
    BvhNode {
        min: load_vec3(a + layout::BVH_MIN),
        max: load_vec3(a + layout::BVH_MAX),
        a: hw::load_u32(a + layout::BVH_A),
        b: hw::load_u32(a + layout::BVH_B),
    }
}

/// BVH node `i`.
pub fn bvh_node(i: u32) -> BvhNode {
    bvh_node_at(bvh_base(), i)
}

/// Address of the parent pointers (`bvh_parents`; 0 if absent).
pub fn bvh_parents_base() -> u32 {
    hw::load_u32(hw::hdr_bvh_parents() + layout::COMPONENT_ADDR)
}

/// Parent node index of BVH node `i` from the parent pointers at `base` (see
/// [`bvh_parents_base`]); `0xFFFFFFFF` for the root.
pub fn bvh_parent_at(base: u32, i: u32) -> u32 {
    hw::load_u32(base + i * layout::BVH_PARENTS_STRIDE)
}

/// Parent node index of BVH node `i` (`0xFFFFFFFF` for the root).
pub fn bvh_parent(i: u32) -> u32 {
    bvh_parent_at(bvh_parents_base(), i)
}

/// Treelet id of BVH node `i`.
pub fn treelet_id(i: u32) -> u32 {
    hw::load_u32(
        hw::load_u32(hw::hdr_treelet_ids() + layout::COMPONENT_ADDR)
            + i * layout::TREELET_IDS_STRIDE,
    )
}

/// Address of the treelet ids (`treelet_ids`; 0 if absent).
pub fn treelet_ids_base() -> u32 {
    hw::load_u32(hw::hdr_treelet_ids() + layout::COMPONENT_ADDR)
}

/// Address of the triangle treelet ids (`tri_treelet_ids`; 0 if absent).
pub fn tri_treelet_ids_base() -> u32 {
    hw::load_u32(hw::hdr_tri_treelet_ids() + layout::COMPONENT_ADDR)
}

/// Triangle treelet id of triangle slot `i` (`0xFFFFFFFF` for a padding slot); triangle
/// treelet ids follow the node treelets' ([`treelet_id`]).
pub fn tri_treelet_id(i: u32) -> u32 {
    hw::load_u32(
        hw::load_u32(hw::hdr_tri_treelet_ids() + layout::COMPONENT_ADDR)
            + i * layout::TRI_TREELET_IDS_STRIDE,
    )
}

/// Address of the triangle slots' leaves (`tri_leaf_ids`; 0 if absent).
pub fn tri_leaf_ids_base() -> u32 {
    hw::load_u32(hw::hdr_tri_leaf_ids() + layout::COMPONENT_ADDR)
}

/// The BVH leaf holding triangle slot `i` (`0xFFFFFFFF` for a padding slot), from the
/// array at `base` (see [`tri_leaf_ids_base`]).
pub fn tri_leaf_at(base: u32, i: u32) -> u32 {
    hw::load_u32(base + i * layout::TRI_LEAF_IDS_STRIDE)
}

/// The `trax.setpipe` modes this chip's TMs offer: bit `m` for mode `m` (see
/// [`super::pipe`]); from the chip config, in the scene header.
pub fn pipe_modes() -> u32 {
    hw::load_u32(hw::hdr_pipe_modes())
}

// ---- Texture coordinates ----

/// Number of triangles with texture coordinates (0 if the scene has none).
pub fn texcoords_count() -> u32 {
    hw::load_u32(hw::hdr_texcoords() + layout::COMPONENT_COUNT)
}

/// Interpolated texture coordinates of triangle `i` at barycentrics `(u, v)`, as
/// `(s, t, 0)`.
pub fn texcoord(i: u32, u: f32, v: f32) -> Vec3 {
    let a =
        hw::load_u32(hw::hdr_texcoords() + layout::COMPONENT_ADDR) + i * layout::TEXCOORDS_STRIDE;
    let w = 1.0 - u - v;
    // Each vertex's `(s, t)` is two f32: `s` at the vertex's offset, `t` 4 bytes after.
    let t1 = a + layout::TEXCOORDS_T1;
    let t2 = a + layout::TEXCOORDS_T2;
    let s = hw::load_f32(a) * w + hw::load_f32(t1) * u + hw::load_f32(t2) * v;
    let t = hw::load_f32(a + 4) * w + hw::load_f32(t1 + 4) * u + hw::load_f32(t2 + 4) * v;
    Vec3::new(s, t, 0.0)
}
