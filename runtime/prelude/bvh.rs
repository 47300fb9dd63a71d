//! Ray/scene intersection: a watertight ray/triangle test (Woop, Benthin and Wald,
//! "Watertight Ray/Triangle Intersection", JCGT 2013), a robust slab test for BVH boxes,
//! and closest-hit / any-hit BVH traversal, with a stack of node indices ([`intersect`],
//! [`occluded`]) or as a resumable state machine with a one-word bit stack and parent
//! pointers ([`Traversal`], thesis §3.2.2), which a streaming ray tracer stops at treelet
//! boundaries and continues later on another TM.

use super::hw;
use super::layout;
use super::math::Vec3;
use super::ray::{Hit, Ray};
use super::scene;
use super::scene::{BvhNode, Triangle};

/// Maximum BVH depth supported by the traversal stack.
pub const STACK_SIZE: u32 = 64;

/// `1 + 2 * gamma(3)` with `gamma(n) = n*eps / (1 - n*eps)`, `eps = 2^-24`: scaling the
/// far slab distance by this makes the box test conservative under f32 rounding.
const SLAB_FAR_SCALE: f32 = 1.000_000_4;

/// Constants of pbrt's bound on the rounding error of a triangle hit's `t` (times
/// `|det|`), from `gamma(n) = n u / (1 - n u)`, `u = 2^-24`, rounded up:
/// `6 gamma(3)` (the `maxE` terms), `6 (gamma(2) + 2 gamma(5))` and `12 gamma(5)` (three
/// times `deltaE = 2 (gamma(2) X Y + gamma(5) (Y + Z) X + gamma(5) (X + Z) Y)` with
/// `X = Y`).
const ERR_T: f32 = 1.072_884e-6;
const ERR_XY: f32 = 4.291_536e-6;
const ERR_Z: f32 = 3.576_280_3e-6;

/// Per-ray constants of the watertight triangle test.
///
/// The edge functions are products of two sheared coordinates, and the scaled distance
/// adds a third factor, so in plain f32 they overflow for coordinates beyond about 1e12 and
/// underflow below about 1e-13. The sheared x and y coordinates are therefore multiplied by
/// a power of two, [`TriRay::scale`], that brings the magnitude of the ray origin and of the
/// scene to about 1: the edge functions and the determinant then stay near 1 and the
/// scaled distance near the hit distance at every scale, and the distance and barycentrics
/// come out unscaled (the factor cancels in their quotients). Multiplying by a power of two
/// is exact, so wherever the plain computation was in range the result is bit for bit the
/// same.
#[derive(Clone, Copy)]
pub struct TriRay {
    pub origin: Vec3,
    pub kx: u32,
    pub ky: u32,
    pub kz: u32,
    pub sx: f32,
    pub sy: f32,
    pub sz: f32,
    /// The power of two the sheared x and y coordinates are multiplied by.
    pub scale: f32,
    /// `scale * |dir[kz]|`: converts a z distance in units of the ray parameter to
    /// scaled units (for the error bound).
    pub scale_dz: f32,
}

impl TriRay {
    /// Precomputes the shear/permutation of `ray` and the scale for triangles whose
    /// coordinates are at most about `bound` in magnitude (for example [`scene_bound`]).
    /// The bound need not be tight: the test stays exact for triangles within a factor of
    /// about 2^±30 of `max(bound, |origin|)`.
    #[inline(always)]
    pub fn new(ray: &Ray, bound: f32) -> TriRay {
        let kz = ray.dir.max_dimension();
        let a: u32 = if kz == 2 { 0 } else { kz + 1 };
        let b: u32 = if a == 2 { 0 } else { a + 1 };
        let dz = ray.dir.get(kz);
        // Swap x and y for a negative z so the winding does not depend on the sign.
        let kx = if dz < 0.0 { b } else { a };
        let ky = if dz < 0.0 { a } else { b };
        let scale = super::math::pow2_scale(super::max(ray.origin.max_abs(), bound));
        TriRay {
            origin: ray.origin,
            kx,
            ky,
            kz,
            sx: ray.dir.get(kx) / dz,
            sy: ray.dir.get(ky) / dz,
            sz: 1.0 / dz,
            scale,
            scale_dz: scale * dz.abs(),
        }
    }

    /// Tests `tri` for a hit with `t_min < t < hit.t`; on a hit updates `hit.t`, `hit.u`,
    /// `hit.v` (not `hit.tri`) and returns true. Edges and vertices shared by two
    /// triangles are hit by at least one of them.
    pub fn intersect(&self, tri: &Triangle, t_min: f32, hit: &mut Hit) -> bool {
        let a = tri.v0 - self.origin;
        let b = tri.v1 - self.origin;
        let c = tri.v2 - self.origin;
        let az = a.get(self.kz);
        let bz = b.get(self.kz);
        let cz = c.get(self.kz);
        let k = self.scale;
        let ax = (a.get(self.kx) - self.sx * az) * k;
        let ay = (a.get(self.ky) - self.sy * az) * k;
        let bx = (b.get(self.kx) - self.sx * bz) * k;
        let by = (b.get(self.ky) - self.sy * bz) * k;
        let cx = (c.get(self.kx) - self.sx * cz) * k;
        let cy = (c.get(self.ky) - self.sy * cz) * k;
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        // Exactly on an edge in single precision: decide in double precision.
        if u == 0.0 || v == 0.0 || w == 0.0 {
            u = ((cx as f64) * (by as f64) - (cy as f64) * (bx as f64)) as f32;
            v = ((ax as f64) * (cy as f64) - (ay as f64) * (cx as f64)) as f32;
            w = ((bx as f64) * (ay as f64) - (by as f64) * (ax as f64)) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return false;
        }
        let det = u + v + w;
        if det == 0.0 {
            return false;
        }
        let azt = self.sz * az;
        let bzt = self.sz * bz;
        let czt = self.sz * cz;
        let t_scaled = u * azt + v * bzt + w * czt;
        // Compare t = t_scaled / det against the interval without dividing.
        if det > 0.0 {
            if t_scaled <= t_min * det || t_scaled >= hit.t * det {
                return false;
            }
        } else if t_scaled >= t_min * det || t_scaled <= hit.t * det {
            return false;
        }
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;
        // Guard the rounding of the division against the interval once more.
        if t <= t_min || t >= hit.t {
            return false;
        }
        // pbrt's conservative test (pbrt-v3 section 3.9.6): a hit closer than the bound on
        // the rounding error of `t` might be behind the origin, as when a ray leaves the
        // surface it starts on ([`super::ray::SurfacePoint`]); reject it. Here x and y
        // carry the scale `k` (the edge functions `k²`) and z is in units of `t`
        // (`z * sz`); the shear's error in x and y involves the plain z, `max_zt * |dz|`,
        // scaled like x and y. pbrt's bound `3 (gamma3 maxE maxZt + deltaE maxZt +
        // deltaZ maxE) / |det|` is compared multiplied by `|det|` (no division), with the
        // largest |x| and |y| taken together and `maxE <= |det|` (u, v, w share a sign).
        let max_zt = super::max(azt.abs(), super::max(bzt.abs(), czt.abs()));
        let max_xy = super::max(
            super::max(ax.abs(), super::max(bx.abs(), cx.abs())),
            super::max(ay.abs(), super::max(by.abs(), cy.abs())),
        );
        let kz = self.scale_dz * max_zt;
        let bound = max_zt * (ERR_T * det.abs() + max_xy * (ERR_XY * max_xy + ERR_Z * kz));
        let t_det = if det > 0.0 { t_scaled } else { -t_scaled };
        if t_det <= bound {
            return false;
        }
        hit.t = t;
        hit.u = v * inv_det;
        hit.v = w * inv_det;
        true
    }
}

/// Largest absolute coordinate of BVH node `n`'s box.
#[inline(always)]
pub fn node_bound(n: &BvhNode) -> f32 {
    super::max(n.min.max_abs(), n.max.max_abs())
}

/// Largest absolute coordinate of the scene: of the BVH's root box, or, without a BVH, of
/// every triangle vertex. The bound [`TriRay::new`] wants.
pub fn scene_bound() -> f32 {
    if scene::bvh_node_count() > 0 {
        return node_bound(&scene::bvh_node_at(scene::bvh_base(), 0));
    }
    let mut m: f32 = 0.0;
    let n = scene::triangle_count();
    let mut i: u32 = 0;
    while i < n {
        let t = scene::triangle(i);
        m = super::max(
            m,
            super::max(t.v0.max_abs(), super::max(t.v1.max_abs(), t.v2.max_abs())),
        );
        i += 1;
    }
    m
}

/// Per-ray constants of the slab test.
#[derive(Clone, Copy)]
pub struct BoxRay {
    pub origin: Vec3,
    /// `1 / dir` per component (±inf for zero components).
    pub inv: Vec3,
    pub neg_x: bool,
    pub neg_y: bool,
    pub neg_z: bool,
}

impl BoxRay {
    /// Precomputes the inverse direction and its signs.
    pub fn new(ray: &Ray) -> BoxRay {
        let inv = Vec3::new(1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z);
        BoxRay {
            origin: ray.origin,
            inv,
            neg_x: inv.x < 0.0,
            neg_y: inv.y < 0.0,
            neg_z: inv.z < 0.0,
        }
    }

    /// Entry distance of the ray into the box `[lo, hi]` clipped to `[t_min, t_max]`, or
    /// `INFINITY` on a miss.
    ///
    /// Robust: near/far planes are chosen by the direction's sign, so a zero direction
    /// component gives ±inf distances, and the 0 × inf = NaN of a ray lying in a slab
    /// plane is ignored by `trax::max`/`trax::min` (IEEE maxNum/minNum): such a ray is
    /// treated as inside that slab. The far distance is scaled up by
    /// `1 + 2 gamma(3)` to absorb rounding.
    pub fn entry(&self, lo: Vec3, hi: Vec3, t_min: f32, t_max: f32) -> f32 {
        let nx = if self.neg_x { hi.x } else { lo.x };
        let fx = if self.neg_x { lo.x } else { hi.x };
        let ny = if self.neg_y { hi.y } else { lo.y };
        let fy = if self.neg_y { lo.y } else { hi.y };
        let nz = if self.neg_z { hi.z } else { lo.z };
        let fz = if self.neg_z { lo.z } else { hi.z };
        let tnx = (nx - self.origin.x) * self.inv.x;
        let tfx = (fx - self.origin.x) * self.inv.x;
        let tny = (ny - self.origin.y) * self.inv.y;
        let tfy = (fy - self.origin.y) * self.inv.y;
        let tnz = (nz - self.origin.z) * self.inv.z;
        let tfz = (fz - self.origin.z) * self.inv.z;
        let near = super::max(super::max(tnx, tny), super::max(tnz, t_min));
        let far = super::min(super::min(tfx, tfy), tfz) * SLAB_FAR_SCALE;
        let far = super::min(far, t_max);
        if near <= far {
            near
        } else {
            super::INFINITY
        }
    }

    /// [`BoxRay::entry`] on a BVH node's box.
    pub fn node_entry(&self, n: &BvhNode, t_min: f32, t_max: f32) -> f32 {
        self.entry(n.min, n.max, t_min, t_max)
    }
}

/// The box and triangle tests a traversal runs: the prelude's robust slab and watertight
/// triangle tests ([`SoftTests`]), or the fused pipelines' semantics
/// ([`super::pipe::PipeTests`]).
///
/// Both take the element's address in simulated memory, so a test loads what it needs
/// in the form it needs (a pipeline: the words, straight into its input registers).
pub trait RayTests {
    /// Entry distance of the ray into the box of the BVH node stored at `node` when it
    /// enters before `t_max`, otherwise `INFINITY`.
    fn box_entry(&self, node: u32, t_max: f32) -> f32;
    /// Tests the triangle stored at `tri`: on a hit closer than `hit.t` updates `hit.t`,
    /// `hit.u` and `hit.v` (not `hit.tri`) and returns true.
    fn tri_hit(&self, tri: u32, hit: &mut Hit) -> bool;
}

/// The prelude's own tests for one ray: [`BoxRay`] and [`TriRay`], hits with
/// `t_min < t < hit.t`. What [`intersect`] and [`occluded`] run.
#[derive(Clone, Copy)]
pub struct SoftTests {
    pub br: BoxRay,
    pub tr: TriRay,
    pub t_min: f32,
}

impl SoftTests {
    /// The tests of `ray` in a scene whose coordinates are at most about `bound` in
    /// magnitude (see [`TriRay::new`]).
    pub fn new(ray: &Ray, t_min: f32, bound: f32) -> SoftTests {
        SoftTests {
            br: BoxRay::new(ray),
            tr: TriRay::new(ray, bound),
            t_min,
        }
    }
}

impl RayTests for SoftTests {
    #[inline(always)]
    fn box_entry(&self, node: u32, t_max: f32) -> f32 {
        let lo = scene::load_vec3(node + layout::BVH_MIN);
        let hi = scene::load_vec3(node + layout::BVH_MAX);
        self.br.entry(lo, hi, self.t_min, t_max)
    }

    #[inline(always)]
    fn tri_hit(&self, tri: u32, hit: &mut Hit) -> bool {
        self.tr
            .intersect(&scene::triangle_stored(tri), self.t_min, hit)
    }
}

/// Tests the triangles of leaf `node` (in the array at `tris`, [`scene::triangles_base`])
/// in order, keeping the closest hit in `hit` (`hit.tri` = the triangle's index); with
/// `any`, stops at the first hit. True if a triangle was hit. The leaf loop of every
/// traversal here.
#[inline(always)]
pub fn leaf_hits<X: RayTests>(x: &X, tris: u32, node: &BvhNode, hit: &mut Hit, any: bool) -> bool {
    let mut found = false;
    let mut i = node.a;
    while i < node.a + node.b {
        if x.tri_hit(tris + i * layout::TRIANGLES_STRIDE, hit) {
            hit.tri = i;
            found = true;
            if any {
                return true;
            }
        }
        i += 1;
    }
    found
}

/// Every triangle of a scene without a BVH, as [`leaf_hits`] tests a leaf.
fn all_triangles_hit(ray: &Ray, t_min: f32, hit: &mut Hit, any: bool) -> bool {
    let x = SoftTests::new(ray, t_min, scene_bound());
    let all = BvhNode {
        min: Vec3::zero(),
        max: Vec3::zero(),
        a: 0,
        b: scene::triangle_count(),
    };
    leaf_hits(&x, scene::triangles_base(), &all, hit, any)
}

/// Closest hit along `ray` with `t_min < t < t_max` over the whole scene (BVH if the
/// scene has one, otherwise every triangle). Counts one ray (`trax.stat 0`).
pub fn intersect(ray: &Ray, t_min: f32, t_max: f32) -> Hit {
    hw::count_ray();
    let mut hit = Hit::none(t_max);
    let base = scene::bvh_base();
    if scene::bvh_node_count() == 0 {
        all_triangles_hit(ray, t_min, &mut hit, false);
        return hit;
    }
    let br = BoxRay::new(ray);
    let mut stack: [u32; 64] = [0; 64];
    let mut sp: usize = 0;
    let mut node = scene::bvh_node_at(base, 0);
    if br.node_entry(&node, t_min, hit.t) == super::INFINITY {
        return hit;
    }
    let x = SoftTests {
        br,
        tr: TriRay::new(ray, node_bound(&node)),
        t_min,
    };
    let tris = scene::triangles_base();
    loop {
        if node.is_leaf() {
            leaf_hits(&x, tris, &node, &mut hit, false);
        } else {
            let left = scene::bvh_node_at(base, node.a);
            let right = scene::bvh_node_at(base, node.a + 1);
            let tl = br.node_entry(&left, t_min, hit.t);
            let tr_ = br.node_entry(&right, t_min, hit.t);
            let hit_l = tl != super::INFINITY;
            let hit_r = tr_ != super::INFINITY;
            if hit_l && hit_r {
                // Visit the nearer child first; the other waits on the stack.
                if tl <= tr_ {
                    stack[sp] = node.a + 1;
                    node = left;
                } else {
                    stack[sp] = node.a;
                    node = right;
                }
                sp += 1;
                continue;
            } else if hit_l {
                node = left;
                continue;
            } else if hit_r {
                node = right;
                continue;
            }
        }
        // Pop the next subtree still in front of the closest hit.
        let mut found = false;
        while sp > 0 {
            sp -= 1;
            let n = scene::bvh_node_at(base, stack[sp]);
            if br.node_entry(&n, t_min, hit.t) != super::INFINITY {
                node = n;
                found = true;
                break;
            }
        }
        if !found {
            return hit;
        }
    }
}

/// True if anything blocks `ray` with `t_min < t < t_max` (shadow rays). Counts one ray.
pub fn occluded(ray: &Ray, t_min: f32, t_max: f32) -> bool {
    hw::count_ray();
    let mut hit = Hit::none(t_max);
    let base = scene::bvh_base();
    if scene::bvh_node_count() == 0 {
        return all_triangles_hit(ray, t_min, &mut hit, true);
    }
    let x = SoftTests::new(ray, t_min, node_bound(&scene::bvh_node_at(base, 0)));
    let tris = scene::triangles_base();
    let mut stack: [u32; 64] = [0; 64];
    let mut sp: usize = 1;
    stack[0] = 0;
    while sp > 0 {
        sp -= 1;
        let node = scene::bvh_node_at(base, stack[sp]);
        if x.br.node_entry(&node, t_min, t_max) == super::INFINITY {
            continue;
        }
        if node.is_leaf() {
            if leaf_hits(&x, tris, &node, &mut hit, true) {
                return true;
            }
        } else {
            stack[sp] = node.a;
            stack[sp + 1] = node.a + 1;
            sp += 2;
        }
    }
    false
}

/// A traversal stack of one bit per BVH level in one word (thesis §3.2.2): the top is the
/// least significant bit, push shifts left (adding 1 when the left child was visited
/// first), pop shifts right. With parent pointers, the bit is all a level needs: coming
/// back up from a child, the traversal visits the other child when the one it comes from
/// was the first.
///
/// A sentinel bit below the first level marks the bottom, so a BVH deeper than 31 levels
/// stops the program with a message instead of losing the oldest bits.
#[derive(Clone, Copy, PartialEq)]
pub struct BitStack {
    /// The stack word: the sentinel, then one bit per level, top at bit 0.
    pub bits: u32,
}

impl BitStack {
    /// The empty stack (the sentinel alone).
    pub fn new() -> BitStack {
        BitStack { bits: 1 }
    }

    /// A stack from its word (as stored in a ray record).
    pub fn from_bits(bits: u32) -> BitStack {
        BitStack { bits }
    }

    /// Pushes a level: whether its left child is visited first.
    #[inline(always)]
    pub fn push(&mut self, left_first: bool) {
        if self.bits >= 0x8000_0000 {
            panic!("BVH deeper than the 31 levels a one-word traversal stack holds");
        }
        self.bits = (self.bits << 1) | (left_first as u32);
    }

    /// Pops the top level.
    #[inline(always)]
    pub fn pop(&mut self) {
        self.bits >>= 1;
    }

    /// Whether the top level visited its left child first.
    #[inline(always)]
    pub fn left_first(&self) -> bool {
        self.bits & 1 == 1
    }
}

/// Where a [`Traversal`]'s arrays are, read once from the scene header: the BVH nodes,
/// their parent pointers (`bvh_parents`), the triangles and the leaf of each triangle
/// slot (`tri_leaf_ids`). A traversal step reads no header field.
#[derive(Clone, Copy)]
pub struct BvhArrays {
    /// Address of node 0 ([`scene::bvh_base`]).
    pub nodes: u32,
    /// Address of triangle 0 ([`scene::triangles_base`]).
    pub tris: u32,
    /// Address of the parent pointers ([`scene::bvh_parents_base`]).
    pub parents: u32,
    /// Address of the slots' leaves ([`scene::tri_leaf_ids_base`]).
    pub leaves: u32,
    /// Triangle slots.
    pub slots: u32,
}

impl BvhArrays {
    /// The scene's.
    pub fn load() -> BvhArrays {
        BvhArrays {
            nodes: scene::bvh_base(),
            tris: scene::triangles_base(),
            parents: scene::bvh_parents_base(),
            leaves: scene::tri_leaf_ids_base(),
            slots: scene::triangle_count(),
        }
    }
}

/// Where the treelet ids are (`treelet_ids` per node, `tri_treelet_ids` per triangle
/// slot), read once from the scene header. A program that reads them gets its BVH laid out
/// in treelets.
#[derive(Clone, Copy)]
pub struct TreeletArrays {
    pub nodes: u32,
    pub tris: u32,
}

impl TreeletArrays {
    /// The scene's.
    pub fn load() -> TreeletArrays {
        TreeletArrays {
            nodes: scene::treelet_ids_base(),
            tris: scene::tri_treelet_ids_base(),
        }
    }
}

/// Step kinds of a [`Traversal`] (the top two bits of its word).
const STEP_ROOT: u32 = 0;
const STEP_PAIR: u32 = 1;
const STEP_LEAF: u32 = 2;
const STEP_UP: u32 = 3;
const NODE_MASK: u32 = 0x3FFF_FFFF;
/// The finished traversal: back up from the root.
const DONE: u32 = STEP_UP << 30;

/// A resumable closest-hit or any-hit BVH traversal (thesis §3.2.2): the nearer child
/// first, a one-word [`BitStack`], parent pointers (`bvh_parents`) to climb back up, early
/// termination (boxes entered beyond the closest hit are skipped). Its whole state is two
/// words (the step and its node, and the stack) plus the ray and its hit record, so a
/// streaming ray can stop after any [`Traversal::step`] and continue on another TM; each
/// step reads the BVH of one treelet ([`Traversal::treelet`]).
///
/// Steps (the next one is decided by the one before):
/// - root: test the root's box;
/// - pair `c`: test the boxes of siblings `c`, `c + 1` (the children of the node above);
///   push whether the left goes first (a lone hit child is pushed as if visited second, so
///   nothing comes back to it) and descend; neither hit: up from their parent;
/// - leaf: test the triangles of the leaf whose first triangle slot is the step's node (the
///   slots' leaves, `tri_leaf_ids`, give the leaf and the run of its slots, so the step
///   reads only triangle-treelet data), then up from that leaf;
/// - up from `x`: the top bit says which child of `x`'s parent went first; if `x` (the
///   left child when `bvh_parents` of `x - 1` is not that parent) was the first, the
///   other child is tested again with the closest hit found since and visited if still
///   ahead; otherwise pop and go up from the parent. Up from the root: done.
///
/// It visits the same nodes in the same order as [`intersect`]'s stack (which also tests
/// a waiting child's box again when popping it), so with the same tests it finds the same
/// hit, bit for bit ([`intersect_bitstack`], [`occluded_bitstack`]).
#[derive(Clone, Copy)]
pub struct Traversal {
    /// The next step's kind (top two bits) and node.
    pub word: u32,
    /// Which child went first at each level above.
    pub stack: BitStack,
}

impl Traversal {
    /// A traversal that starts at the root.
    pub fn new() -> Traversal {
        Traversal {
            word: STEP_ROOT << 30,
            stack: BitStack::new(),
        }
    }

    /// A traversal from its two words (as stored in a ray record).
    pub fn from_words(word: u32, stack: u32) -> Traversal {
        Traversal {
            word,
            stack: BitStack::from_bits(stack),
        }
    }

    /// True when the traversal is over.
    pub fn is_done(&self) -> bool {
        self.word == DONE
    }

    /// Ends the traversal (an any-hit query that found its answer).
    pub fn finish(&mut self) {
        self.word = DONE;
    }

    /// True when the next step tests a leaf's triangles (its data is a triangle treelet).
    pub fn at_leaf(&self) -> bool {
        self.word >> 30 == STEP_LEAF
    }

    /// The next step's node: the root (0), the first of a sibling pair, a leaf's first
    /// triangle slot, or the node to go up from.
    pub fn node(&self) -> u32 {
        self.word & NODE_MASK
    }

    /// The treelet whose data the next step reads: the node's (`treelet_ids`), or for a
    /// leaf step its first triangle's (`tri_treelet_ids`). Meaningless once done.
    pub fn treelet(&self, t: &TreeletArrays) -> u32 {
        let node = self.word & NODE_MASK;
        if self.word >> 30 == STEP_LEAF {
            hw::load_u32(t.tris + node * 4)
        } else {
            hw::load_u32(t.nodes + node * 4)
        }
    }

    /// Descends into the node stored at `n`, whose box was hit: its children's boxes next,
    /// or a leaf's triangles (the node word then names the leaf's first triangle slot).
    #[inline(always)]
    fn descend(&mut self, n: u32) {
        let step = if hw::load_u32(n + layout::BVH_B) != 0 {
            STEP_LEAF
        } else {
            STEP_PAIR
        };
        self.word = (step << 30) | hw::load_u32(n + layout::BVH_A);
    }

    /// Runs steps while the traversal is not done and `stay` accepts the next one (a
    /// streaming kernel: while it reads the current treelet); see [`Traversal::step`].
    /// True if it stopped because `stay` refused a step.
    pub fn run<X: RayTests, F: Fn(&Traversal) -> bool>(
        &mut self,
        x: &X,
        b: &BvhArrays,
        hit: &mut Hit,
        any: bool,
        stay: F,
    ) -> bool {
        // Locals, so the state stays in registers between steps.
        let mut t = *self;
        let mut h = *hit;
        let mut refused = false;
        while !t.is_done() {
            if !stay(&t) {
                refused = true;
                break;
            }
            t.step(x, b, &mut h, any);
        }
        *self = t;
        *hit = h;
        refused
    }

    /// Runs the next step with the tests `x` against `hit` (the closest hit so far, its
    /// `t` the search limit) on the BVH at `b`. With `any`, the traversal ends at the
    /// first triangle hit. Not to be called once done.
    #[inline(always)]
    pub fn step<X: RayTests>(&mut self, x: &X, b: &BvhArrays, hit: &mut Hit, any: bool) {
        let kind = self.word >> 30;
        let node = self.word & NODE_MASK;
        if kind == STEP_PAIR {
            let left = b.nodes + node * layout::BVH_NODES_STRIDE;
            let right = left + layout::BVH_NODES_STRIDE;
            let tl = x.box_entry(left, hit.t);
            let tr = x.box_entry(right, hit.t);
            let hit_l = tl != super::INFINITY;
            let hit_r = tr != super::INFINITY;
            if hit_l && hit_r {
                let left_first = tl <= tr;
                self.stack.push(left_first);
                self.descend(if left_first { left } else { right });
            } else if hit_l {
                // Pushed as the second child: nothing to come back for.
                self.stack.push(false);
                self.descend(left);
            } else if hit_r {
                self.stack.push(true);
                self.descend(right);
            } else {
                self.word = (STEP_UP << 30) | scene::bvh_parent_at(b.parents, node);
            }
        } else if kind == STEP_UP {
            let parent = scene::bvh_parent_at(b.parents, node);
            // `node` is the right child when its left neighbour has the same parent.
            let right = scene::bvh_parent_at(b.parents, node - 1) == parent;
            if right != self.stack.left_first() {
                // `node` went first: the other child, if still ahead of the closest hit.
                let other = if right { node - 1 } else { node + 1 };
                let n = b.nodes + other * layout::BVH_NODES_STRIDE;
                if x.box_entry(n, hit.t) != super::INFINITY {
                    self.descend(n);
                    return;
                }
            }
            self.stack.pop();
            self.word = (STEP_UP << 30) | parent;
        } else if kind == STEP_LEAF {
            // The leaf and its run of slots.
            let leaf = scene::tri_leaf_at(b.leaves, node);
            let mut end = node + 1;
            while end < b.slots && scene::tri_leaf_at(b.leaves, end) == leaf {
                end += 1;
            }
            let tris = BvhNode {
                min: Vec3::zero(),
                max: Vec3::zero(),
                a: node,
                b: end - node,
            };
            if leaf_hits(x, b.tris, &tris, hit, any) && any {
                self.word = DONE;
            } else {
                self.word = (STEP_UP << 30) | leaf;
            }
        } else {
            if x.box_entry(b.nodes, hit.t) == super::INFINITY {
                self.word = DONE;
            } else {
                self.descend(b.nodes);
            }
        }
    }
}

/// The whole [`Traversal`] of `ray` at once, with the prelude's tests.
fn traverse_bitstack(ray: &Ray, t_min: f32, hit: &mut Hit, any: bool) -> bool {
    if scene::bvh_node_count() == 0 {
        return all_triangles_hit(ray, t_min, hit, any);
    }
    let b = BvhArrays::load();
    let x = SoftTests::new(ray, t_min, node_bound(&scene::bvh_node_at(b.nodes, 0)));
    let mut t = Traversal::new();
    while !t.is_done() {
        t.step(&x, &b, hit, any);
    }
    hit.is_hit()
}

/// [`intersect`] by the resumable bit-stack [`Traversal`]: the same hit, bit for bit.
/// Counts one ray.
pub fn intersect_bitstack(ray: &Ray, t_min: f32, t_max: f32) -> Hit {
    hw::count_ray();
    let mut hit = Hit::none(t_max);
    traverse_bitstack(ray, t_min, &mut hit, false);
    hit
}

/// [`occluded`] by the resumable bit-stack [`Traversal`]: the same answer. Counts one
/// ray.
pub fn occluded_bitstack(ray: &Ray, t_min: f32, t_max: f32) -> bool {
    hw::count_ray();
    let mut hit = Hit::none(t_max);
    traverse_bitstack(ray, t_min, &mut hit, true)
}
