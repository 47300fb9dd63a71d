//! STRaTA treelet-streaming path tracer (Kopta 2016, §3.1–3.2 and §7.1): the path tracer of
//! `pathtracer.rs` (Lambertian surfaces, emissive triangles and point lights, one shadow
//! ray per vertex, cosine-weighted bounces, `max_depth` vertices and `spp` samples per
//! pixel from the scene header) written for a chip with a ray stream memory, so that a TM
//! works for a long time on rays that all read one treelet (a cache-sized piece of the
//! BVH or of the triangles) and keeps it in its L1.
//!
//! - Rays live in the stream memory (`trax::stream`), in one buffer per treelet: node
//!   treelet `t` in box buffer `t % H`, triangle treelet `t` in triangle buffer
//!   `H + t % H`, `H` = half the buffers (treelet ids are folded when there are more
//!   treelets than buffers). A TM's threads drain its current buffer: each reads a ray and
//!   runs its traversal (`trax::bvh::Traversal`: nearer child first, a one-word bit stack,
//!   parent pointers, early termination) for as long as the next step reads the same
//!   buffer's treelet, then writes it to the buffer of the treelet it needs next. When
//!   the buffer is empty, `stream::schedule()` waits for the TM's other threads and picks
//!   the next buffer (the fullest by default).
//! - After each schedule the TM configures its units for the buffer's class: the box
//!   pipeline for node treelets, the triangle pipeline for triangle treelets (§3.2.3), when
//!   the chip has them (header `pipe_modes`; `--set pipelines.enabled=false` makes a chip
//!   without). Otherwise the same tests run in software with the same bits
//!   (`trax::pipe::PipeTests`), so the image does not depend on the pipelines. Shading
//!   runs in whatever mode the TM is in, on the general-purpose units left over.
//! - A ray is one 48-byte record (§3.2.1): origin, direction, `t` (the closest hit so far,
//!   or a shadow ray's limit), the traversal's step word, the hit triangle (a shadow ray:
//!   the triangle it leaves), the bit stack, the path (pixel and sample, vertex depth,
//!   shadow flag) and the path throughput in RGB9E5 (one shared exponent). Everything the
//!   shader needs travels with the ray or is recomputed from the triangle (§7.1.3):
//!   barycentrics by testing the hit triangle again, the normal from the triangle, and the
//!   light sample by drawing the same random numbers again (every vertex seeds its own
//!   streams from (pixel, sample, depth)).
//! - Many rays in flight: the root treelet's buffer is first filled with camera rays up to
//!   `stream::capacity()`. Then rays are replaced one for one (§3.2.1): a finished camera
//!   or bounce ray by its vertex's shadow ray, a shadow ray by the vertex's bounce ray, a
//!   path's last ray by the camera ray of the next path. Paths are (pixel, sample) pairs
//!   handed out by a chip-wide counter, so every sample of the frame is work for any TM.
//! - The image does not depend on ray order, chip or timing: each path vertex writes the
//!   radiance it adds (direct light, or the background a ray escaped to; the camera
//!   ray's emission apart) once, as one RGB9E5 word, into its own slot in global memory —
//!   one store, no load — and after the last ray (`schedule()` returns `None`) and a
//!   barrier the pixels are reduced in sample and vertex order into the framebuffer.
//!
//! Needs a chip with a stream memory (`--config strata`, or `--set
//! stream_memory.capacity_bytes=...`); at most `MAX_SLOTS` / (`max_depth` + 1) (pixel,
//! sample) pairs and 16 vertices per path.

use trax::bvh::{BvhArrays, TreeletArrays, Traversal};
use trax::pipe::PipeTests;
use trax::ray::{SurfacePoint, NO_HIT};
use trax::stream::Record;
use trax::{Hit, Ray, Vec3};

/// Radiance slots a frame may have: `max_depth + 1` per (pixel, sample) pair (one per
/// vertex and one for the camera ray's emission), 4 bytes each.
const MAX_SLOTS: usize = 6 << 20;
/// Global registers: paths handed out by the initial fill and afterwards, two barriers.
const FILL_REG: u32 = 0;
const NEXT_REG: u32 = 1;
const FILLED_REG: u32 = 2;
const DONE_REG: u32 = 3;

/// Radiance each path vertex adds, RGB9E5 (path `p`, slot `k`: `p * (max_depth + 1) + k`;
/// slot `max_depth` is the camera ray's emission).
static mut RADIANCE: [u32; MAX_SLOTS] = [0; MAX_SLOTS];
/// Treelet ids whose index range the kernel keeps ([`FIRST`], [`END`]); a step in a
/// treelet beyond them asks `treelet_ids` / `tri_treelet_ids` instead.
const MAX_TREELETS: usize = 1 << 16;
/// Per treelet id (node treelets: node indices; triangle treelets: triangle slots), the
/// first index and one past the last, found once from the treelet id arrays: a step whose
/// node is in the current treelet's range stays on the TM without reading them.
static mut FIRST: [u32; MAX_TREELETS] = [0; MAX_TREELETS];
static mut END: [u32; MAX_TREELETS] = [0; MAX_TREELETS];
/// TMs a chip may have (the chip config's limit).
const MAX_TMS: usize = 4096;
/// Per TM, the last buffer visit in which one of its threads found the buffer empty: the
/// visit is over for the TM's other threads too (they stop reading and schedule), so rays
/// that other TMs keep writing to a hot buffer do not hold a few threads there while the
/// rest of the TM waits in `schedule()`.
static mut VISIT_OVER: [u32; MAX_TMS] = [0; MAX_TMS];

/// Bits of the path word: shadow flag, vertex depth, path id.
const SHADOW: u32 = 1;
const DEPTH_SHIFT: u32 = 1;
const DEPTH_MASK: u32 = 0xF;
const PATH_SHIFT: u32 = 5;
/// Largest `max_depth` the path word holds.
const DEPTH_LIMIT: u32 = DEPTH_MASK + 1;
/// Paths the path word can name.
const PATH_LIMIT: u32 = 1 << (32 - PATH_SHIFT);

/// What the kernel knows about the frame and the chip.
#[derive(Clone, Copy)]
struct Frame {
    width: u32,
    spp: u32,
    max_depth: u32,
    /// Paths of the frame (`width * height * spp`).
    paths: u32,
    /// Paths started by the initial fill.
    initial: u32,
    /// Box buffers (`0..half`) and triangle buffers (`half..2 * half`).
    half: u32,
    /// The chip's TMs can be configured as the box and triangle pipelines.
    pipes: bool,
    cam: trax::Camera,
    bvh: BvhArrays,
    treelets: TreeletArrays,
}

/// A ray in registers: the record's contents unpacked.
#[derive(Clone, Copy)]
struct StreamRay {
    ray: Ray,
    /// The closest hit so far (closest-hit rays) or the limit (shadow rays).
    t: f32,
    /// The hit triangle so far (closest-hit rays), or the triangle a shadow ray leaves.
    tri: u32,
    trav: Traversal,
    /// Path id, depth and shadow flag.
    path: u32,
    /// Path throughput before this ray's vertex (RGB9E5).
    throughput: u32,
}

impl StreamRay {
    fn pack(&self) -> Record {
        [
            self.ray.origin.x.to_bits(),
            self.ray.origin.y.to_bits(),
            self.ray.origin.z.to_bits(),
            self.ray.dir.x.to_bits(),
            self.ray.dir.y.to_bits(),
            self.ray.dir.z.to_bits(),
            self.t.to_bits(),
            self.trav.word,
            self.tri,
            self.trav.stack.bits,
            self.path,
            self.throughput,
        ]
    }

    fn unpack(r: &Record) -> StreamRay {
        let f = |i: usize| f32::from_bits(r[i]);
        StreamRay {
            ray: Ray::new(Vec3::new(f(0), f(1), f(2)), Vec3::new(f(3), f(4), f(5))),
            t: f(6),
            tri: r[8],
            trav: Traversal::from_words(r[7], r[9]),
            path: r[10],
            throughput: r[11],
        }
    }

    /// A new ray from `origin` along `dir` at the root of the BVH (counted as a ray cast).
    fn new(origin: Vec3, dir: Vec3, t: f32, tri: u32, path: u32, throughput: u32) -> StreamRay {
        trax::count_ray();
        StreamRay {
            ray: Ray::new(origin, dir),
            t,
            tri,
            trav: Traversal::new(),
            path,
            throughput,
        }
    }

    fn shadow(&self) -> bool {
        self.path & SHADOW != 0
    }

    fn depth(&self) -> u32 {
        (self.path >> DEPTH_SHIFT) & DEPTH_MASK
    }

    fn id(&self) -> u32 {
        self.path >> PATH_SHIFT
    }
}

// ---- RGB9E5: three 9-bit mantissas with a shared 5-bit exponent (bias 15) ----

/// 2^e as an f32 (`e` in -126..=127).
fn pow2(e: i32) -> f32 {
    f32::from_bits(((e + 127) as u32) << 23)
}

/// `c` (non-negative) in RGB9E5, rounded to nearest; channels above 65408 saturate.
fn rgb9e5(c: Vec3) -> u32 {
    let clampc = |x: f32| trax::min(trax::max(x, 0.0), 65408.0);
    let (r, g, b) = (clampc(c.x), clampc(c.y), clampc(c.z));
    let m = trax::max(r, trax::max(g, b));
    // floor(log2(m)) from the exponent bits, at least -16.
    let e_m = ((m.to_bits() >> 23) as i32 - 127).max(-16);
    let mut e = e_m + 1 + 15;
    let mut scale = pow2(e - 15 - 9);
    if (m / scale + 0.5) as u32 >= 512 {
        e += 1;
        scale = pow2(e - 15 - 9);
    }
    let q = |x: f32| ((x / scale + 0.5) as u32).min(511);
    q(r) | (q(g) << 9) | (q(b) << 18) | ((e as u32) << 27)
}

fn from_rgb9e5(w: u32) -> Vec3 {
    let scale = pow2((w >> 27) as i32 - 15 - 9);
    Vec3::new(
        (w & 511) as f32 * scale,
        ((w >> 9) & 511) as f32 * scale,
        ((w >> 18) & 511) as f32 * scale,
    )
}

// ---- Shading ----

/// Random streams of a path: the camera's, and per vertex the light sample's and the
/// bounce's, each seeded from (path, event) so a draw can be repeated anywhere.
fn seed(path: u32, event: u32) {
    trax::seed_pixel(path, event)
}

fn light_event(depth: u32) -> u32 {
    1 + 2 * depth
}

fn bounce_event(depth: u32) -> u32 {
    2 + 2 * depth
}

/// Records `c` as the radiance of path `path`'s slot `slot` (written once per path and
/// slot; black needs no store, the slots start at 0).
fn accumulate(f: &Frame, path: u32, slot: u32, c: Vec3) {
    if c.is_black() {
        return;
    }
    let i = (path * (f.max_depth + 1) + slot) as usize;
    unsafe { RADIANCE[i] = rgb9e5(c) };
}

/// A shadow ray's direction and limit, and what it brings (times the path throughput)
/// when nothing blocks it.
#[derive(Clone, Copy)]
struct LightSample {
    dir: Vec3,
    t_max: f32,
    contribution: Vec3,
}

/// One light for the vertex at `origin` (unit normal `n` facing the incoming ray, diffuse
/// albedo `albedo`), chosen uniformly among the emitting triangles (as one light) and
/// the point lights, weighted by their number; `None` when it cannot reach the vertex.
/// Draws from the vertex's light stream, seeded here, so it can be drawn again.
fn light_sample(path: u32, depth: u32, origin: Vec3, n: Vec3, albedo: Vec3) -> Option<LightSample> {
    seed(path, light_event(depth));
    let emitters = trax::scene::emitter_count();
    let points = trax::scene::point_light_count();
    let has_emitters = if emitters > 0 { 1 } else { 0 };
    let lights = has_emitters + points;
    if lights == 0 {
        return None;
    }
    let k = ((trax::rand() * lights as f32) as u32).min(lights - 1);
    let brdf = albedo.scale(core::f32::consts::FRAC_1_PI * lights as f32);
    if k < has_emitters {
        let e = ((trax::rand() * emitters as f32) as u32).min(emitters - 1);
        let tri_index = trax::scene::emitter(e);
        let tri = trax::scene::triangle(tri_index);
        let q = trax::sampling::triangle_point(&tri);
        let eg = trax::sampling::emitter_geometry(&tri, origin, q);
        let cos_surf = n.dot(eg.dir);
        let cos_light = eg.normal.dot(eg.dir).abs();
        let emission = trax::scene::triangle_material(tri_index).emission;
        if cos_surf <= 0.0 || cos_light <= 0.0 {
            return None;
        }
        // pdf (area) = 1 / (emitters * area); solid-angle conversion cos_light / d².
        let g = cos_surf * cos_light / eg.dist2 * eg.area * emitters as f32;
        // Stop just short of the light so its own triangle does not occlude.
        return Some(LightSample {
            dir: eg.dir,
            t_max: eg.dist * (1.0 - 1e-4),
            contribution: brdf * emission.scale(g),
        });
    }
    let light = trax::scene::point_light(k - has_emitters);
    let to_light = light.position - origin;
    let dist2 = to_light.length_squared();
    let dist = to_light.length();
    let l = to_light.scale(1.0 / dist);
    let cos = n.dot(l);
    if cos <= 0.0 {
        return None;
    }
    Some(LightSample {
        dir: l,
        t_max: dist,
        contribution: brdf * light.color.scale(cos / dist2),
    })
}

/// The triangle's unit normal turned towards `dir`'s side (`dir` the incoming ray turned
/// around, or a shadow ray's direction).
fn facing(tri: u32, dir: Vec3) -> Vec3 {
    let n = trax::scene::triangle(tri).normal();
    if n.dot(dir) < 0.0 {
        -n
    } else {
        n
    }
}

/// After the vertex of depth `depth` at `origin` (normal `n`, triangle `tri`): the bounce
/// ray, or the next path's camera ray when the path ends there.
fn bounce(
    f: &Frame,
    path: u32,
    depth: u32,
    origin: Vec3,
    n: Vec3,
    tri: u32,
    throughput: Vec3,
) -> Option<StreamRay> {
    let albedo = trax::scene::triangle_material(tri).diffuse;
    if depth + 1 >= f.max_depth || albedo.is_black() {
        return next_path(f);
    }
    seed(path, bounce_event(depth));
    let dir = trax::sampling::cosine_hemisphere(n);
    // Cosine sampling: brdf * cos / pdf = albedo.
    let word = (path << PATH_SHIFT) | ((depth + 1) << DEPTH_SHIFT);
    Some(StreamRay::new(
        origin,
        dir,
        trax::INFINITY,
        NO_HIT,
        word,
        rgb9e5(throughput * albedo),
    ))
}

/// The camera ray of path `p`.
fn camera_ray(f: &Frame, p: u32) -> StreamRay {
    let pixel = p / f.spp;
    seed(p, 0);
    let r = f.cam.jittered_ray(pixel % f.width, pixel / f.width);
    StreamRay::new(
        r.origin,
        r.dir,
        trax::INFINITY,
        NO_HIT,
        p << PATH_SHIFT,
        rgb9e5(Vec3::splat(1.0)),
    )
}

/// The next path's camera ray, if any path is left.
fn next_path(f: &Frame) -> Option<StreamRay> {
    let p = f.initial + trax::atomic_inc(NEXT_REG);
    if p < f.paths {
        Some(camera_ray(f, p))
    } else {
        None
    }
}

/// Shades `r`, whose traversal is over (`hit` = what it found): adds the path's radiance
/// and returns the ray that replaces it, if any.
fn finish(f: &Frame, r: &StreamRay, hit: &Hit, x: &PipeTests) -> Option<StreamRay> {
    let path = r.id();
    let depth = r.depth();
    let throughput = from_rgb9e5(r.throughput);
    if r.shadow() {
        // The vertex the shadow ray leaves: its origin, its triangle, the normal facing
        // the light, and the same light sample drawn again.
        let origin = r.ray.origin;
        let n = facing(r.tri, r.ray.dir);
        if !hit.is_hit() {
            let albedo = trax::scene::triangle_material(r.tri).diffuse;
            if let Some(ls) = light_sample(path, depth, origin, n, albedo) {
                accumulate(f, path, depth, throughput * ls.contribution);
            }
        }
        return bounce(f, path, depth, origin, n, r.tri, throughput);
    }
    if !hit.is_hit() {
        accumulate(f, path, depth, throughput * trax::scene::background());
        return next_path(f);
    }
    let tri = trax::scene::triangle(hit.tri);
    // The barycentrics: the hit triangle's test again (the same bits).
    let h = x.tri(&tri);
    let full = Hit {
        t: h.t,
        tri: hit.tri,
        u: h.u,
        v: h.v,
    };
    let m = trax::scene::triangle_material(hit.tri);
    if depth == 0 && !m.emission.is_black() {
        accumulate(f, path, f.max_depth, m.emission);
    }
    // New rays start just off the surface, by the hit point's rounding error.
    let sp = SurfacePoint::new(&r.ray, &full, &tri);
    let origin = sp.origin();
    if let Some(ls) = light_sample(path, depth, origin, sp.n, m.diffuse) {
        let word = (path << PATH_SHIFT) | (depth << DEPTH_SHIFT) | SHADOW;
        return Some(StreamRay::new(
            origin,
            ls.dir,
            ls.t_max,
            hit.tri,
            word,
            r.throughput,
        ));
    }
    bounce(f, path, depth, origin, sp.n, hit.tri, throughput)
}

/// `id` folded into `0..half` (no division unless there are more treelets than buffers).
fn fold(id: u32, half: u32) -> u32 {
    if id < half {
        id
    } else {
        id % half
    }
}

/// The buffer of the treelet `t`'s next step reads.
fn buffer_of(f: &Frame, t: &Traversal) -> u32 {
    let id = t.treelet(&f.treelets);
    if t.at_leaf() {
        f.half + fold(id, f.half)
    } else {
        fold(id, f.half)
    }
}

/// The `trax.setpipe` mode of a TM working on buffer `b`: the box or triangle pipeline
/// if the chip has them, else general purpose.
fn mode_of(f: &Frame, b: u32) -> u32 {
    if !f.pipes {
        0
    } else if b < f.half {
        1
    } else {
        2
    }
}

/// Records, for the treelet ids in `ids[0..n]` (one per node or slot), each id's first
/// index and one past its last; this thread's share of the indices.
fn find_ranges(ids: u32, n: u32) {
    let threads = trax::num_threads();
    let chunk = (n + threads - 1) / threads;
    let start = trax::global_id() * chunk;
    let end = n.min(start + chunk);
    let id_at = |i: u32| trax::load_u32(ids + 4 * i);
    let mut i = start;
    while i < end {
        let id = id_at(i);
        if (id as usize) < MAX_TREELETS {
            if i == 0 || id_at(i - 1) != id {
                unsafe { FIRST[id as usize] = i };
            }
            if i + 1 == n || id_at(i + 1) != id {
                unsafe { END[id as usize] = i + 1 };
            }
        }
        i += 1;
    }
}

/// The index range of the treelet of buffer `b` (without folding, the only one there):
/// node indices for a box buffer, triangle slots for a triangle buffer; empty when
/// unknown.
fn range_of(f: &Frame, b: u32) -> (u32, u32) {
    let id = if b < f.half { b } else { b - f.half };
    if (id as usize) < MAX_TREELETS {
        unsafe { (FIRST[id as usize], END[id as usize]) }
    } else {
        (0, 0)
    }
}

/// Works on `r` while its next step reads buffer `b`'s treelet (index range `range`, see
/// [`range_of`]); then writes it to the
/// buffer it needs, or, once its traversal is over, shades it and goes on with the ray
/// that replaces it.
fn process(f: &Frame, mut r: StreamRay, b: u32, mode: u32, range: (u32, u32)) {
    let (first, end) = range;
    let tri_buffer = b >= f.half;
    loop {
        let x = PipeTests::new(&r.ray, mode);
        let mut hit = Hit::none(r.t);
        if !r.shadow() {
            hit.tri = r.tri;
        }
        // Steps in this buffer's treelet (no lookup), or in another that folds into it.
        let stay = |t: &Traversal| {
            let n = t.node();
            (t.at_leaf() == tri_buffer && first <= n && n < end) || buffer_of(f, t) == b
        };
        if r.trav.run(&x, &f.bvh, &mut hit, r.shadow(), stay) {
            let next = buffer_of(f, &r.trav);
            if !r.shadow() {
                r.t = hit.t;
                r.tri = hit.tri;
            }
            trax::stream::write(next, &r.pack());
            return;
        }
        match finish(f, &r, &hit, &x) {
            Some(n) => r = n,
            None => return,
        }
    }
}

fn trax_main() {
    let capacity = trax::stream::capacity();
    let buffers = trax::stream::buffers();
    if capacity == 0 || buffers < 2 {
        panic!("strata.rs needs a chip with a ray stream memory of at least 2 buffers (--config strata)");
    }
    if trax::scene::bvh_node_count() == 0 {
        panic!("strata.rs needs a scene with triangles");
    }
    let width = trax::scene::width();
    let pixels = width * trax::scene::height();
    let spp = trax::scene::spp().max(1);
    let max_depth = trax::scene::max_depth().max(1);
    if max_depth > DEPTH_LIMIT {
        panic!("strata.rs follows paths of at most {} vertices, not {}", DEPTH_LIMIT, max_depth);
    }
    let paths = pixels as u64 * spp as u64;
    let slots = paths * (max_depth as u64 + 1);
    if slots > MAX_SLOTS as u64 || paths >= PATH_LIMIT as u64 {
        panic!(
            "strata.rs renders at most {} radiance slots, not {} pixels x {} samples x {} (depth + 1): fewer pixels, samples or bounces",
            MAX_SLOTS,
            pixels,
            spp,
            max_depth + 1
        );
    }
    let paths = paths as u32;
    // Sampled simulation follows the frame along the paths finished: every path's last
    // ray takes the next one from NEXT_REG (`next_path`), so it ends at `paths`.
    trax::declare_work(NEXT_REG, paths);
    let f = Frame {
        width,
        spp,
        max_depth,
        paths,
        initial: paths.min(capacity),
        half: buffers / 2,
        pipes: trax::pipe::available(),
        cam: trax::Camera::load(),
        bvh: BvhArrays::load(),
        treelets: TreeletArrays::load(),
    };
    find_ranges(f.treelets.nodes, trax::scene::bvh_node_count());
    find_ranges(f.treelets.tris, trax::scene::triangle_count());
    // Fill the root treelet's buffer with camera rays, then every thread streams (after
    // the barrier, which the ranges found above also need).
    let root = buffer_of(&f, &Traversal::new());
    loop {
        let p = trax::atomic_inc(FILL_REG);
        if p >= f.initial {
            break;
        }
        trax::stream::write(root, &camera_ray(&f, p).pack());
    }
    trax::barrier(FILLED_REG);
    let mut rec: Record = [0; trax::stream::RECORD_WORDS];
    let tm = trax::tm_id() as usize;
    // Every thread of a TM sees the same schedules, so they agree on the visit number.
    let mut visit: u32 = 0;
    while let Some(b) = trax::stream::schedule() {
        visit += 1;
        let mode = mode_of(&f, b);
        let range = range_of(&f, b);
        if mode == 1 {
            trax::pipe::use_box_pipeline();
        } else if mode == 2 {
            trax::pipe::use_triangle_pipeline();
        }
        while unsafe { VISIT_OVER[tm] } != visit {
            if !trax::stream::read(&mut rec) {
                // Only the first of the TM's threads to find the buffer empty stores the
                // flag (the others see it by now): a global store goes to DRAM, and one
                // from every thread cost up to 32 DRAM writes a visit.
                if unsafe { VISIT_OVER[tm] } != visit {
                    unsafe { VISIT_OVER[tm] = visit };
                }
                break;
            }
            process(&f, StreamRay::unpack(&rec), b, mode, range);
        }
    }
    // Every path is done: each pixel is the mean of its samples, added in sample and
    // slot order.
    trax::barrier(DONE_REG);
    let inv_spp = 1.0 / spp as f32;
    let per_path = max_depth + 1;
    let mut i = trax::global_id();
    while i < pixels {
        let mut c = Vec3::zero();
        let first = (i * spp * per_path) as usize;
        for k in 0..(spp * per_path) as usize {
            c += from_rgb9e5(unsafe { RADIANCE[first + k] });
        }
        trax::scene::set_pixel_index(i, c.scale(inv_spp));
        i += trax::num_threads();
    }
}
