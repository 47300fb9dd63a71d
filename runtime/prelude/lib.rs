//! `trax`: the kernel prelude, written in TRaX-Rust.
//!
//! The same source is compiled by the trax compiler for the TRaX machine (`hw_trax.rs`:
//! every machine operation is one extension instruction) and by rustc for the host
//! (`hw_host.rs`: threads, atomics and a host copy of simulated memory), so a kernel
//! gives the same results on both. Everything outside `hw_*.rs` and `simd.rs` stays
//! within the TRaX-Rust subset.
//!
//! Map:
//! - this file: thread ids, clock, `rand`/`seed_pixel`, global registers (atomics, barriers,
//!   semaphores), `min`/`max`/`invsqrt`, `count_ray`, raw simulated-memory access;
//! - [`stat`]: the statistics counters (`trax::stat::add`);
//! - [`math`]: `Vec3` (points, directions, linear RGB) with operators;
//! - [`libm`]: `sinf`, `cos`, `atan2f`, `pow`, ... for f32 and f64 (C names), the same
//!   bits on the machine and on the host;
//! - [`scene`]: header fields, triangles, normals, texture coordinates, materials,
//!   emitters, point lights, BVH nodes, framebuffer writes, pixels handed out to threads
//!   from a chip-wide counter (`pixel_share`);
//! - [`camera`]: primary rays (`abi::Camera` semantics, row 0 at the top);
//! - [`ray`], [`bvh`]: rays, hit records, watertight triangle test, robust slab test,
//!   closest-hit and any-hit traversal;
//! - [`sampling`]: cosine-weighted hemisphere, disk, sphere and triangle sampling;
//! - [`pipe`]: the fused box/triangle intersection pipelines;
//! - [`stream`]: the STRaTA ray stream memory (write, read, schedule rays per buffer);
//! - `simd` (host file; compiler builtin on TRaX): `f32x4`, `i32x4`;
//! - `lang` (TRaX only): `Option`, `Result`, `Ordering` — Rust's prelude types, which
//!   the host takes from `core`;
//! - [`layout`]: byte layouts of the scene data;
//! - `host` (host only): the runner used by `trax native` and tests.

#[cfg(target_arch = "mips")]
#[path = "hw_trax.rs"]
mod hw;
#[cfg(not(target_arch = "mips"))]
#[path = "hw_host.rs"]
mod hw;

#[cfg(not(target_arch = "mips"))]
pub mod simd;

/// Host only: `trax::libm` under the C names, so a host-built kernel's `x.sin()` runs it.
#[cfg(not(target_arch = "mips"))]
pub mod libm_host;

/// `Option`, `Result` and `Ordering` on the machine (the host uses `core`'s).
#[cfg(target_arch = "mips")]
pub mod lang;

pub mod bvh;
pub mod camera;
pub mod layout;
pub mod libm;
pub mod math;
pub mod pipe;
pub mod ray;
pub mod sampling;
pub mod scene;
pub mod stream;

pub use camera::Camera;
pub use math::Vec3;
pub use ray::{Hit, Ray};
pub use scene::{set_pixel, BvhNode, Material, PointLight, Triangle};

/// Host runner API (host only): run a kernel over a memory image on host threads.
#[cfg(not(target_arch = "mips"))]
pub mod host {
    pub use super::hw::{
        framebuffer_segment, host_main, host_ptr, image_bytes, parse_image, pipe_box_test,
        pipe_tri_test, pipe_tri_u, pipe_tri_v, run_image, run_image_stats, run_image_with, seed,
        set_pipe_box, set_pipe_general, set_pipe_tri, stream_capacity, stream_read_end,
        stream_read_start, stream_read_word, stream_schedule, stream_size, stream_write_end,
        stream_write_start, stream_write_word, Image, RunError, RunStats, NUM_GLOBAL_REGS,
    };
}

/// Positive infinity.
pub const INFINITY: f32 = f32::INFINITY;
/// Pi.
pub const PI: f32 = std::f32::consts::PI;

// ---- Thread identity and time ----

/// Chip-wide unique index of this hardware thread (`tm_id * threads_per_tm + thread_id`).
pub fn global_id() -> u32 {
    hw::global_id()
}

/// Total number of hardware threads.
pub fn num_threads() -> u32 {
    hw::num_threads()
}

/// Index of this thread within its TM.
pub fn thread_id() -> u32 {
    hw::thread_id()
}

/// Index of this thread's TM.
pub fn tm_id() -> u32 {
    hw::tm_id()
}

/// Number of TMs.
pub fn num_tms() -> u32 {
    hw::num_tms()
}

/// Low 32 bits of the cycle counter (on the host: nanoseconds since start).
pub fn clock() -> u32 {
    hw::clock()
}

/// Next deterministic random number in `[0, 1)` from this thread's stream: at start-up the
/// thread's own (it depends on the thread's global id), after [`seed_pixel`] the stream of
/// that pixel and sample.
pub fn rand() -> f32 {
    hw::rand()
}

/// Makes the following [`rand`] draws those of sample `sample` of pixel `pixel` (and the
/// run's `--seed`), whichever thread, TM or chip runs it and in `trax native` alike: one
/// `trax.seed` instruction. Call it before each sample so that images do not depend on the
/// chip. Any pair of numbers may serve as (pixel, sample).
pub fn seed_pixel(pixel: u32, sample: u32) {
    hw::seed(pixel, sample)
}

// ---- Global registers, barriers and semaphores ----

/// Atomically increments global register `reg`; returns the old value.
pub fn atomic_inc(reg: u32) -> u32 {
    hw::atomic_inc(reg)
}

/// Atomically decrements global register `reg`; returns the old value.
pub fn atomic_dec(reg: u32) -> u32 {
    hw::atomic_dec(reg)
}

/// Atomically adds `v` to global register `reg` (wrapping); returns the old value.
pub fn atomic_add(reg: u32, v: u32) -> u32 {
    hw::atomic_add(reg, v)
}

/// Reads global register `reg`.
pub fn global_read(reg: u32) -> u32 {
    hw::global_read(reg)
}

/// Writes global register `reg`.
pub fn global_write(reg: u32, v: u32) {
    hw::global_write(reg, v)
}

/// Declares the kernel's work counter for sampled simulation (`trax run --sample`): the
/// kernel hands out `items` work items (pixels, paths, tiles, ...) from global register
/// `counter`, one `atomic_inc(counter)` (or `atomic_add` of a block) per item, so that a
/// run can be cut into equal strata of items. Thread 0 records it in global registers
/// `layout::WORK_COUNTER_REG` and `layout::WORK_ITEMS_REG`; other threads do nothing. Call
/// it before the first item is taken. Kernels that take pixels with
/// `scene::pixel_share` need not: sampling follows its counter by default.
pub fn declare_work(counter: u32, items: u32) {
    if hw::global_id() == 0 {
        hw::global_write(layout::WORK_ITEMS_REG, items);
        hw::global_write(layout::WORK_COUNTER_REG, counter + 1);
    }
}

/// Atomically increments `reg`, wrapping to 0 when it reaches the thread count; returns
/// the old value.
pub fn inc_reset(reg: u32) -> u32 {
    hw::inc_reset(reg)
}

/// Waits until every live thread has reached barrier `reg`.
pub fn barrier(reg: u32) {
    hw::barrier(reg)
}

/// Waits until semaphore register `reg` is positive, then decrements it.
pub fn sem_acquire(reg: u32) {
    hw::sem_acquire(reg)
}

/// Increments semaphore register `reg`.
pub fn sem_release(reg: u32) {
    hw::sem_release(reg)
}

// ---- Floating point ----

/// IEEE minNum of `a` and `b` (`trax.fmin`; a NaN operand is ignored).
pub fn min(a: f32, b: f32) -> f32 {
    hw::fmin(a, b)
}

/// IEEE maxNum of `a` and `b` (`trax.fmax`).
pub fn max(a: f32, b: f32) -> f32 {
    hw::fmax(a, b)
}

/// `1 / sqrt(x)` (`trax.invsqrt`).
pub fn invsqrt(x: f32) -> f32 {
    hw::invsqrt(x)
}

/// `x` clamped to `[lo, hi]`.
pub fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    math::clampf(x, lo, hi)
}

// ---- Statistics ----

/// Counts one ray cast (statistics counter 0, `trax.stat 0`); the BVH traversal in
/// [`bvh`] calls it once per ray.
pub fn count_ray() {
    hw::count_ray()
}

/// The statistics counters: 32 per chip, summed over every thread, reported by `trax run`
/// (`counters` in the stats document and its summary) and by `trax native` alike.
/// Counter 0 counts rays (the BVH traversal adds one per ray); the others are the
/// kernel's own.
pub mod stat {
    /// Number of counters (`0..COUNTERS`).
    pub const COUNTERS: u32 = 32;
    /// Counter 0: rays cast (the traversals of [`crate::bvh`] count them).
    pub const RAYS: u32 = 0;

    /// Adds `n` to counter `counter` (`0..COUNTERS`; another index stops the program).
    /// One zero-cost instruction (`trax.statadd`) on the machine: it takes no cycle in
    /// the timing model (computing its operands does).
    pub fn add(counter: u32, n: u32) {
        super::hw::stat_add(counter, n)
    }

    /// Adds 1 to counter `counter`.
    pub fn inc(counter: u32) {
        super::hw::stat_add(counter, 1)
    }
}

// ---- Raw simulated memory ----

/// Loads the word at simulated address `addr` (4-byte aligned).
pub fn load_u32(addr: u32) -> u32 {
    hw::load_u32(addr)
}

/// Loads the f32 at simulated address `addr`.
pub fn load_f32(addr: u32) -> f32 {
    hw::load_f32(addr)
}

/// Stores a word at simulated address `addr`.
pub fn store_u32(addr: u32, v: u32) {
    hw::store_u32(addr, v)
}

/// Stores an f32 at simulated address `addr`.
pub fn store_f32(addr: u32, v: f32) {
    hw::store_f32(addr, v)
}
