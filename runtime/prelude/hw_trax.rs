//! TRaX side of the machine interface: every operation is one real instruction, emitted
//! through the compiler's builtin macros (`__trax_op!` with a mnemonic from the runtime's
//! instruction table, `__trax_symbol_addr!`). Compiled by the trax compiler only.
//!
//! Simulated memory is the real address space here, so loads and stores are plain
//! pointer accesses.

// ---- Thread identity and time ----

/// Thread index within its TM.
pub fn thread_id() -> u32 {
    __trax_op!("trax.tid")
}

/// Index of the thread's TM.
pub fn tm_id() -> u32 {
    __trax_op!("trax.tmid")
}

/// Chip-wide unique thread index.
pub fn global_id() -> u32 {
    __trax_op!("trax.gid")
}

/// Total hardware threads.
pub fn num_threads() -> u32 {
    __trax_op!("trax.nthreads")
}

/// Number of TMs.
pub fn num_tms() -> u32 {
    __trax_op!("trax.ntms")
}

/// Low 32 bits of the cycle counter.
pub fn clock() -> u32 {
    __trax_op!("trax.clock")
}

/// Next per-thread random number in [0, 1).
pub fn rand() -> f32 {
    __trax_op!("trax.rand")
}

/// Reseeds this thread's random stream for `pixel`, `sample` (`trax.seed`).
pub fn seed(pixel: u32, sample: u32) {
    __trax_op!("trax.seed", pixel, sample);
}

// ---- Global registers ----

pub fn atomic_inc(reg: u32) -> u32 {
    __trax_op!("trax.atominc", reg)
}

pub fn atomic_dec(reg: u32) -> u32 {
    __trax_op!("trax.atomdec", reg)
}

pub fn atomic_add(reg: u32, v: u32) -> u32 {
    __trax_op!("trax.atomadd", reg, v)
}

pub fn global_read(reg: u32) -> u32 {
    __trax_op!("trax.gread", reg)
}

pub fn global_write(reg: u32, v: u32) {
    __trax_op!("trax.gwrite", reg, v);
}

pub fn inc_reset(reg: u32) -> u32 {
    __trax_op!("trax.increset", reg)
}

pub fn barrier(reg: u32) {
    __trax_op!("trax.barrier", reg);
}

pub fn sem_acquire(reg: u32) {
    __trax_op!("trax.semacq", reg);
}

pub fn sem_release(reg: u32) {
    __trax_op!("trax.semrel", reg);
}

// ---- Floating point ----

pub fn fmin(a: f32, b: f32) -> f32 {
    __trax_op!("trax.fmin", a, b)
}

pub fn fmax(a: f32, b: f32) -> f32 {
    __trax_op!("trax.fmax", a, b)
}

pub fn invsqrt(x: f32) -> f32 {
    __trax_op!("trax.invsqrt", x)
}

// ---- Statistics ----

/// Statistics counter 0: one ray cast.
pub fn count_ray() {
    __trax_op!("trax.stat", 0);
}

/// Statistics counter `counter` += `n` (a fault past the counters).
pub fn stat_add(counter: u32, n: u32) {
    __trax_op!("trax.statadd", counter, n);
}

// ---- Simulated memory ----

pub fn load_u32(addr: u32) -> u32 {
    unsafe { *(addr as *const u32) }
}

pub fn load_f32(addr: u32) -> f32 {
    unsafe { *(addr as *const f32) }
}

pub fn store_u32(addr: u32, v: u32) {
    unsafe {
        *(addr as *mut u32) = v;
    }
}

pub fn store_f32(addr: u32, v: f32) {
    unsafe {
        *(addr as *mut f32) = v;
    }
}

// ---- Scene header fields, generated from abi::SceneHeader (prelude::render_header_fields) ----

pub fn hdr_magic() -> u32 {
    __trax_symbol_addr!("__trax_scene_magic")
}

pub fn hdr_version() -> u32 {
    __trax_symbol_addr!("__trax_scene_version")
}

pub fn hdr_width() -> u32 {
    __trax_symbol_addr!("__trax_scene_width")
}

pub fn hdr_height() -> u32 {
    __trax_symbol_addr!("__trax_scene_height")
}

pub fn hdr_inv_width() -> u32 {
    __trax_symbol_addr!("__trax_scene_inv_width")
}

pub fn hdr_inv_height() -> u32 {
    __trax_symbol_addr!("__trax_scene_inv_height")
}

pub fn hdr_spp() -> u32 {
    __trax_symbol_addr!("__trax_scene_spp")
}

pub fn hdr_max_depth() -> u32 {
    __trax_symbol_addr!("__trax_scene_max_depth")
}

pub fn hdr_epsilon() -> u32 {
    __trax_symbol_addr!("__trax_scene_epsilon")
}

pub fn hdr_seed() -> u32 {
    __trax_symbol_addr!("__trax_scene_seed")
}

pub fn hdr_background() -> u32 {
    __trax_symbol_addr!("__trax_scene_background")
}

pub fn hdr_camera() -> u32 {
    __trax_symbol_addr!("__trax_scene_camera")
}

pub fn hdr_framebuffer() -> u32 {
    __trax_symbol_addr!("__trax_scene_framebuffer")
}

pub fn hdr_bvh_nodes() -> u32 {
    __trax_symbol_addr!("__trax_scene_bvh_nodes")
}

pub fn hdr_triangles() -> u32 {
    __trax_symbol_addr!("__trax_scene_triangles")
}

pub fn hdr_normals() -> u32 {
    __trax_symbol_addr!("__trax_scene_normals")
}

pub fn hdr_texcoords() -> u32 {
    __trax_symbol_addr!("__trax_scene_texcoords")
}

pub fn hdr_material_ids() -> u32 {
    __trax_symbol_addr!("__trax_scene_material_ids")
}

pub fn hdr_materials() -> u32 {
    __trax_symbol_addr!("__trax_scene_materials")
}

pub fn hdr_emitters() -> u32 {
    __trax_symbol_addr!("__trax_scene_emitters")
}

pub fn hdr_point_lights() -> u32 {
    __trax_symbol_addr!("__trax_scene_point_lights")
}

pub fn hdr_bvh_parents() -> u32 {
    __trax_symbol_addr!("__trax_scene_bvh_parents")
}

pub fn hdr_treelet_ids() -> u32 {
    __trax_symbol_addr!("__trax_scene_treelet_ids")
}

pub fn hdr_tri_treelet_ids() -> u32 {
    __trax_symbol_addr!("__trax_scene_tri_treelet_ids")
}

pub fn hdr_tri_leaf_ids() -> u32 {
    __trax_symbol_addr!("__trax_scene_tri_leaf_ids")
}

pub fn hdr_stream_rays() -> u32 {
    __trax_symbol_addr!("__trax_scene_stream_rays")
}

pub fn hdr_stream_ray_bytes() -> u32 {
    __trax_symbol_addr!("__trax_scene_stream_ray_bytes")
}

pub fn hdr_stream_buffers() -> u32 {
    __trax_symbol_addr!("__trax_scene_stream_buffers")
}

pub fn hdr_pipe_modes() -> u32 {
    __trax_symbol_addr!("__trax_scene_pipe_modes")
}

// ---- end of the scene header fields ----

// ---- Ray streams (STRaTA): one instruction each ----

pub fn stream_write_start(buffer: u32) {
    __trax_op!("trax.strwstart", buffer);
}

pub fn stream_write_word(w: u32) {
    __trax_op!("trax.strw", w);
}

pub fn stream_write_end() {
    __trax_op!("trax.strwend");
}

pub fn stream_read_start() -> u32 {
    __trax_op!("trax.strrstart")
}

pub fn stream_read_word() -> u32 {
    __trax_op!("trax.strr")
}

pub fn stream_read_end() {
    __trax_op!("trax.strrend");
}

pub fn stream_size(buffer: u32) -> u32 {
    __trax_op!("trax.strsize", buffer)
}

pub fn stream_schedule() -> u32 {
    __trax_op!("trax.strsched")
}

pub fn stream_capacity() -> u32 {
    __trax_op!("trax.strcap")
}

// ---- Fused pipelines (inputs in cop2 registers, see the runtime's COP2_REGS) ----

/// `trax.boxtest` of the ray `(o, inv)` against the box `[lo, hi]` (loads the ray too).
pub fn pipe_box_test(o: [f32; 3], inv: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> f32 {
    pipe_load_ray(o, inv);
    pipe_box(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])
}

/// `trax.tritest` of the ray `(o, d)` against the triangle `(a, b, c)` (loads the ray too).
pub fn pipe_tri_test(o: [f32; 3], d: [f32; 3], a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> f32 {
    pipe_load_ray(o, d);
    pipe_tri(a, b, c)
}

/// Loads a ray into the pipelines' input registers (cop2 0..5: origin, then the inverse
/// direction for box tests or the direction for triangle tests); they keep it for
/// [`pipe_box`] and [`pipe_tri`].
pub fn pipe_load_ray(o: [f32; 3], v: [f32; 3]) {
    __trax_mtc2!(0, o[0]);
    __trax_mtc2!(1, o[1]);
    __trax_mtc2!(2, o[2]);
    __trax_mtc2!(3, v[0]);
    __trax_mtc2!(4, v[1]);
    __trax_mtc2!(5, v[2]);
}

/// `trax.boxtest` on the loaded ray and the box `[lo, hi]` (by coordinates, so they go
/// from the registers they were loaded into straight to the pipeline's).
pub fn pipe_box(lx: f32, ly: f32, lz: f32, hx: f32, hy: f32, hz: f32) -> f32 {
    __trax_mtc2!(6, lx);
    __trax_mtc2!(7, ly);
    __trax_mtc2!(8, lz);
    __trax_mtc2!(9, hx);
    __trax_mtc2!(10, hy);
    __trax_mtc2!(11, hz);
    __trax_op!("trax.boxtest")
}

/// `trax.tritest` on the loaded ray and the triangle `(a, b, c)`.
pub fn pipe_tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> f32 {
    __trax_mtc2!(12, a[0]);
    __trax_mtc2!(13, a[1]);
    __trax_mtc2!(14, a[2]);
    __trax_mtc2!(15, b[0]);
    __trax_mtc2!(16, b[1]);
    __trax_mtc2!(17, b[2]);
    __trax_mtc2!(18, c[0]);
    __trax_mtc2!(19, c[1]);
    __trax_mtc2!(20, c[2]);
    __trax_op!("trax.tritest")
}

pub fn pipe_tri_u() -> f32 {
    __trax_mfc2!(21)
}

pub fn pipe_tri_v() -> f32 {
    __trax_mfc2!(22)
}

// ---- The pipelines' tests in software (the shared semantics compiled as kernel code) ----

#[path = "../src/pipes.rs"]
mod pipes;

/// `trax.fmin`/`trax.fmax` under the names the shared pipeline semantics use.
mod fops {
    pub fn fmin(a: f32, b: f32) -> f32 {
        super::fmin(a, b)
    }
    pub fn fmax(a: f32, b: f32) -> f32 {
        super::fmax(a, b)
    }
}

pub fn soft_box_test(o: [f32; 3], inv: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> f32 {
    pipes::box_test(o, inv, lo, hi)
}

pub fn soft_tri_test(
    o: [f32; 3],
    d: [f32; 3],
    a: [f32; 3],
    b: [f32; 3],
    c: [f32; 3],
) -> (f32, f32, f32) {
    pipes::tri_test(o, d, a, b, c)
}

pub fn set_pipe_general() {
    __trax_op!("trax.setpipe", 0);
}

pub fn set_pipe_box() {
    __trax_op!("trax.setpipe", 1);
}

pub fn set_pipe_tri() {
    __trax_op!("trax.setpipe", 2);
}
