//! Host side of the machine interface (compiled by rustc only, for `trax native` and the
//! runtime's tests): kernel threads are host threads, ids live in thread-locals, global
//! registers are atomics, and simulated memory is a host copy of a memory image file
//! (the runtime's `image.rs`, included here so both sides read and write one format),
//! accessed word by word. A store outside the image's writable segments panics, as it
//! faults on the machine (the host does not check loads in the gaps between segments:
//! the emulator is the exact reference for bad addresses).

use std::cell::{Cell, RefCell};
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Instant;

#[path = "../src/counters.rs"]
#[allow(dead_code)]
mod counters;
#[path = "../src/fops.rs"]
mod fops;
#[path = "../src/image.rs"]
pub mod image;
#[path = "../src/pipes.rs"]
mod pipes;
#[path = "../src/rng.rs"]
mod rng;
#[path = "../src/streams.rs"]
#[allow(dead_code)]
mod streams;

use super::layout;

/// Number of chip-wide global registers on the host.
pub const NUM_GLOBAL_REGS: u32 = 256;
/// Stack size of each kernel thread on the host.
const KERNEL_STACK_BYTES: usize = 16 << 20;

/// Largest address span (lowest to highest segment byte) the host runner maps.
const MAX_SPAN_BYTES: u64 = 1 << 30;

/// Everything a kernel thread can wait for, under one lock (so a deadlock between
/// barriers and stream schedulers is seen): barriers, the ray stream memory and the TMs'
/// stream schedulers (the runtime's `streams.rs`, the emulator's exact semantics).
struct Barriers {
    /// Threads that have not returned from `trax_main`.
    live: u32,
    /// Per register: threads waiting, and a generation bumped at each release.
    arrived: Vec<u32>,
    generation: Vec<u64>,
    /// The ray stream memory (shape from the scene header).
    streams: streams::StreamMemory,
    /// The TMs' stream schedulers.
    sched: streams::StreamScheduler,
    /// What each thread (by global id) waits for, for deadlock reports.
    waits: Vec<Wait>,
    /// A kernel thread panicked: waiting threads stop too.
    aborted: bool,
}

/// What a kernel thread waits for.
#[derive(Clone, Copy, PartialEq)]
enum Wait {
    /// Nothing (running or finished).
    None,
    /// A barrier on this global register.
    Barrier(u32),
    /// Its TM's stream scheduler (`trax.strsched`).
    Schedule,
}

/// One simulated chip: memory, global registers and barrier state.
///
/// Memory is one dense word array covering every segment, from the lowest segment address
/// to the end of the highest; gaps between segments read as zero (the emulator, not the
/// host, is the exact reference for bad accesses inside that span).
struct Machine {
    /// Address of `mem[0]`.
    base: u32,
    mem: Vec<AtomicU32>,
    /// The image's segments (initial contents), for writing the result back.
    segments: Vec<image::Segment>,
    /// Writable ranges `[start, end)`, sorted.
    writable: Vec<(u64, u64)>,
    globals: Vec<AtomicU32>,
    barriers: Mutex<Barriers>,
    barrier_cv: Condvar,
    num_tms: u32,
    threads_per_tm: u32,
    seed: u32,
    start: Instant,
    /// Statistics counters of threads that have finished (`stat_add`; 0: rays).
    stats: [AtomicU64; counters::NUM_STATS],
    /// `trax.setpipe` mode per TM.
    pipe_modes: Vec<AtomicU32>,
}

#[derive(Clone, Copy)]
struct Ids {
    tid: u32,
    tmid: u32,
    gid: u32,
}

thread_local! {
    /// The machine of this kernel thread (null outside kernel threads); see
    /// [`with_machine`] for why it stays valid.
    static MACHINE: Cell<*const Machine> = const { Cell::new(std::ptr::null()) };
    static IDS: Cell<Ids> = const { Cell::new(Ids { tid: 0, tmid: 0, gid: 0 }) };
    static RNG: Cell<Option<rng::Rng>> = const { Cell::new(None) };
    /// Rays counted by this thread (added to the machine's total when it finishes).
    static STATS: Cell<[u64; counters::NUM_STATS]> = const { Cell::new([0; counters::NUM_STATS]) };
    /// Barycentric outputs of the last triangle-pipeline test (cop2 21 and 22).
    static TRI_UV: Cell<[f32; 2]> = const { Cell::new([0.0; 2]) };
    /// The ray inputs of the pipelines (cop2 0..5) loaded by `pipe_load_ray`.
    static PIPE_RAY: Cell<[[f32; 3]; 2]> = const { Cell::new([[0.0; 3]; 2]) };
    /// The ray being written to a stream (buffer, words) and the one being read.
    static STREAM_WRITE: RefCell<Option<(u32, Vec<u32>)>> = const { RefCell::new(None) };
    static STREAM_READ: RefCell<Option<(Vec<u32>, usize)>> = const { RefCell::new(None) };
}

fn with_machine<R>(f: impl FnOnce(&Machine) -> R) -> R {
    let p = MACHINE.with(|m| m.get());
    if p.is_null() {
        panic!("trax: machine operation called outside a kernel thread");
    }
    // SAFETY: `p` is only non-null while this thread runs the kernel inside `run_image`,
    // where it points into an `Arc<Machine>` owned by the thread's `LiveGuard`; the guard
    // nulls the pointer before it releases the `Arc`. `Machine` is `Sync` (atomics and
    // a mutex), so a shared reference on this thread is sound.
    f(unsafe { &*p })
}

fn ids() -> Ids {
    IDS.with(|c| c.get())
}

impl Machine {
    fn word(&self, addr: u32, what: &str) -> &AtomicU32 {
        if !addr.is_multiple_of(4) {
            panic!("trax: misaligned {what} at address {addr:#010x}");
        }
        if let Some(w) = self.mem.get((addr.wrapping_sub(self.base) / 4) as usize) {
            if addr >= self.base {
                return w;
            }
        }
        if addr < layout::SCENE_HEADER_ADDR {
            panic!("trax: null pointer {what} at address {addr:#010x}");
        }
        panic!("trax: {what} at unmapped address {addr:#010x}");
    }

    /// The word at `addr` for a store: it must lie in a writable segment.
    fn word_mut(&self, addr: u32) -> &AtomicU32 {
        let w = self.word(addr, "store");
        let a = addr as u64;
        if !self.writable.iter().any(|&(s, e)| s <= a && a + 4 <= e) {
            let seg = self.segments.iter().find(|s| s.holds(addr, 4));
            match seg {
                Some(s) => panic!(
                    "trax: store to read-only memory at address {addr:#010x} (segment `{}`, {})",
                    s.name, s.perms
                ),
                None => panic!("trax: store at unmapped address {addr:#010x}"),
            }
        }
        w
    }

    fn global(&self, reg: u32) -> &AtomicU32 {
        match self.globals.get(reg as usize) {
            Some(g) => g,
            None => panic!("trax: global register {reg} out of range (0..{NUM_GLOBAL_REGS})"),
        }
    }

    fn num_threads(&self) -> u32 {
        self.num_tms * self.threads_per_tm
    }

    /// Releases every barrier that all live threads have reached.
    fn release_complete_barriers(&self, b: &mut Barriers) {
        let mut any = false;
        for r in 0..b.arrived.len() {
            if b.arrived[r] > 0 && b.arrived[r] >= b.live {
                b.arrived[r] = 0;
                b.generation[r] += 1;
                any = true;
            }
        }
        if any {
            self.barrier_cv.notify_all();
        }
    }

    /// The lock over barriers and streams.
    fn waits(&self) -> std::sync::MutexGuard<'_, Barriers> {
        self.barriers.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Waits on the condition variable until `done`; panics when another kernel thread
    /// panicked, and reports a deadlock (every live thread waiting for another) as a panic
    /// naming the threads.
    fn wait_until<'a>(
        &self,
        mut b: std::sync::MutexGuard<'a, Barriers>,
        mut done: impl FnMut(&Barriers) -> bool,
    ) -> std::sync::MutexGuard<'a, Barriers> {
        let blocked = |b: &Barriers| b.arrived.iter().sum::<u32>() + b.sched.waiting;
        loop {
            // A panic elsewhere stops every waiter, even one its exit released.
            if b.aborted {
                drop(b);
                panic!("trax: stopped: another kernel thread panicked");
            }
            if done(&b) {
                break;
            }
            if b.live > 0 && blocked(&b) >= b.live {
                // The other waiters stop once this thread's panic has been reported (its
                // `LiveGuard` marks the run aborted).
                let report = self.deadlock_report(&b);
                drop(b);
                panic!("{report}");
            }
            b = self.barrier_cv.wait(b).unwrap_or_else(|e| e.into_inner());
        }
        b
    }

    /// "trax: deadlock: ..." with every waiting thread, grouped.
    fn deadlock_report(&self, b: &Barriers) -> String {
        let mut s = format!(
            "trax: deadlock: all {} live thread(s) wait for one another, and none can run:",
            b.live
        );
        let n = self.threads_per_tm;
        let what = |w: Wait, gid: u32| match w {
            Wait::Barrier(r) => format!(
                "trax.barrier G[{r}] ({} of {} live threads arrived)",
                b.arrived[r as usize], b.live
            ),
            Wait::Schedule => {
                let t = &b.sched.tms[(gid / n) as usize];
                if t.idle {
                    "trax.strsched (its TM drained and every ray buffer is empty: waiting for a ray)".to_string()
                } else {
                    format!(
                        "trax.strsched (waiting for {} more live thread(s) of its TM)",
                        t.live.saturating_sub(t.waiting)
                    )
                }
            }
            Wait::None => String::new(),
        };
        let rows: Vec<(u32, String)> = (0..b.waits.len() as u32)
            .filter(|&g| b.waits[g as usize] != Wait::None)
            .map(|g| (g, what(b.waits[g as usize], g)))
            .collect();
        let mut i = 0;
        while i < rows.len() {
            let mut j = i + 1;
            while j < rows.len()
                && rows[j].1 == rows[i].1
                && rows[j].0 / n == rows[i].0 / n
                && rows[j].0 == rows[i].0 + (j - i) as u32
            {
                j += 1;
            }
            let who = if j - i == 1 {
                format!("thread {}", rows[i].0)
            } else {
                format!("threads {}-{}", rows[i].0, rows[j - 1].0)
            };
            s += &format!("\n  {who} (TM {}): {}", rows[i].0 / n, rows[i].1);
            i = j;
        }
        s
    }
}

// ---- Thread identity and time ----

pub fn thread_id() -> u32 {
    ids().tid
}

pub fn tm_id() -> u32 {
    ids().tmid
}

pub fn global_id() -> u32 {
    ids().gid
}

pub fn num_threads() -> u32 {
    with_machine(|m| m.num_threads())
}

pub fn num_tms() -> u32 {
    with_machine(|m| m.num_tms)
}

/// Host clock: low 32 bits of nanoseconds since the run started (not deterministic).
pub fn clock() -> u32 {
    with_machine(|m| m.start.elapsed().as_nanos() as u32)
}

pub fn rand() -> f32 {
    RNG.with(|c| {
        let mut r = match c.get() {
            Some(r) => r,
            None => with_machine(|m| rng::Rng::new(m.seed, ids().gid)),
        };
        let x = r.next_f32();
        c.set(Some(r));
        x
    })
}

/// `trax.seed`: this thread's stream becomes the one of `pixel`, `sample`.
pub fn seed(pixel: u32, sample: u32) {
    let r = with_machine(|m| rng::Rng::for_sample(m.seed, pixel, sample));
    RNG.with(|c| c.set(Some(r)));
}

// ---- Global registers ----

pub fn atomic_inc(reg: u32) -> u32 {
    with_machine(|m| m.global(reg).fetch_add(1, Ordering::SeqCst))
}

pub fn atomic_dec(reg: u32) -> u32 {
    with_machine(|m| m.global(reg).fetch_sub(1, Ordering::SeqCst))
}

pub fn atomic_add(reg: u32, v: u32) -> u32 {
    with_machine(|m| m.global(reg).fetch_add(v, Ordering::SeqCst))
}

/// Reads a global register. Yields the host thread, so spin loops on it stay cheap.
pub fn global_read(reg: u32) -> u32 {
    let v = with_machine(|m| m.global(reg).load(Ordering::SeqCst));
    std::thread::yield_now();
    v
}

pub fn global_write(reg: u32, v: u32) {
    with_machine(|m| m.global(reg).store(v, Ordering::SeqCst))
}

pub fn inc_reset(reg: u32) -> u32 {
    with_machine(|m| {
        let n = m.num_threads();
        let g = m.global(reg);
        let mut old = g.load(Ordering::SeqCst);
        loop {
            let new = if old.wrapping_add(1) >= n { 0 } else { old + 1 };
            match g.compare_exchange(old, new, Ordering::SeqCst, Ordering::SeqCst) {
                Ok(v) => return v,
                Err(v) => old = v,
            }
        }
    })
}

pub fn barrier(reg: u32) {
    with_machine(|m| {
        m.global(reg);
        let r = reg as usize;
        let gid = ids().gid as usize;
        let mut b = m.waits();
        let gen = b.generation[r];
        b.arrived[r] += 1;
        b.waits[gid] = Wait::Barrier(reg);
        m.release_complete_barriers(&mut b);
        let mut b = m.wait_until(b, |b| b.generation[r] != gen);
        b.waits[gid] = Wait::None;
    })
}

pub fn sem_acquire(reg: u32) {
    loop {
        let ok = with_machine(|m| {
            let g = m.global(reg);
            let v = g.load(Ordering::SeqCst);
            v > 0
                && g.compare_exchange(v, v - 1, Ordering::SeqCst, Ordering::SeqCst)
                    .is_ok()
        });
        if ok {
            return;
        }
        std::thread::yield_now();
    }
}

pub fn sem_release(reg: u32) {
    with_machine(|m| m.global(reg).fetch_add(1, Ordering::SeqCst));
}

// ---- Floating point: the exact TRaX semantics, shared with the emulator ----

pub fn fmin(a: f32, b: f32) -> f32 {
    fops::fmin(a, b)
}

pub fn fmax(a: f32, b: f32) -> f32 {
    fops::fmax(a, b)
}

pub fn invsqrt(x: f32) -> f32 {
    fops::invsqrt(x)
}

/// Host address of the simulated byte at `addr`, for C kernels run natively (`trax
/// native k.c`), which dereference the scene's pointers: memory is one dense span, so
/// pointer arithmetic within a component stays in it. Panics outside the span, as a load
/// would. The pointer is valid while the kernel thread runs; accesses through it are
/// plain (non-atomic) host accesses to the words the Rust side reads with atomics, which
/// is race-free as long as kernel threads do not write the same word concurrently (the
/// same rule the machine's memory has for plain loads and stores).
pub fn host_ptr(addr: u32) -> *mut u8 {
    with_machine(|m| {
        let w = m.word(addr & !3, "access");
        w.as_ptr().cast::<u8>().wrapping_add((addr & 3) as usize)
    })
}

// ---- Fused pipelines: the exact TRaX semantics, shared with the emulator ----

/// A pipeline test needs its TM in the pipeline's `trax.setpipe` mode (as on the machine).
/// Outside a kernel thread (host unit tests) there is no TM and no mode to check.
fn need_pipe_mode(needed: u32, instr: &str) {
    if MACHINE.with(|m| m.get().is_null()) {
        return;
    }
    let name = |m: u32| match m {
        0 => "general-purpose",
        1 => "box-pipeline",
        _ => "triangle-pipeline",
    };
    let mode = with_machine(|m| m.pipe_modes[ids().tmid as usize].load(Ordering::SeqCst));
    if mode != needed {
        panic!(
            "trax: {instr} while this TM's units are in {} mode (needs trax.setpipe {needed}, {} mode)",
            name(mode),
            name(needed)
        );
    }
}

fn set_pipe(mode: u32) {
    if MACHINE.with(|m| m.get().is_null()) {
        return;
    }
    with_machine(|m| m.pipe_modes[ids().tmid as usize].store(mode, Ordering::SeqCst));
}

/// `trax.boxtest`: loads the ray `(o, inv)` (kept, as the machine's cop2 0..5 keep it)
/// and tests it against the box `[lo, hi]`.
pub fn pipe_box_test(o: [f32; 3], inv: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> f32 {
    pipe_load_ray(o, inv);
    pipe_box(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])
}

/// `trax.tritest`: loads the ray `(o, d)` (kept) and tests it against `(a, b, c)`.
pub fn pipe_tri_test(o: [f32; 3], d: [f32; 3], a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> f32 {
    pipe_load_ray(o, d);
    pipe_tri(a, b, c)
}

/// The ray in the pipelines' input registers (cop2 0..5), per thread as on the machine.
pub fn pipe_load_ray(o: [f32; 3], v: [f32; 3]) {
    PIPE_RAY.with(|r| r.set([o, v]));
}

pub fn pipe_box(lx: f32, ly: f32, lz: f32, hx: f32, hy: f32, hz: f32) -> f32 {
    need_pipe_mode(1, "trax.boxtest");
    let [o, inv] = PIPE_RAY.with(|r| r.get());
    pipes::box_test(o, inv, [lx, ly, lz], [hx, hy, hz])
}

pub fn pipe_tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> f32 {
    need_pipe_mode(2, "trax.tritest");
    let [o, d] = PIPE_RAY.with(|r| r.get());
    let (t, u, v) = pipes::tri_test(o, d, a, b, c);
    TRI_UV.with(|uv| uv.set([u, v]));
    t
}

pub fn pipe_tri_u() -> f32 {
    TRI_UV.with(|uv| uv.get()[0])
}

pub fn pipe_tri_v() -> f32 {
    TRI_UV.with(|uv| uv.get()[1])
}

/// The pipelines' tests in software (any mode).
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

/// The TM's `trax.setpipe` mode (checked by the pipeline tests; no timing on the host).
pub fn set_pipe_general() {
    set_pipe(0);
}
pub fn set_pipe_box() {
    set_pipe(1);
}
pub fn set_pipe_tri() {
    set_pipe(2);
}

// ---- Ray streams: the emulator's semantics (the runtime's `streams.rs`) ----

/// `trax.strwstart`: begins a ray for buffer `buffer`.
pub fn stream_write_start(buffer: u32) {
    with_machine(|m| {
        if m.waits().streams.buffer(buffer).is_none() {
            panic!("trax: ray stream index {buffer} out of range");
        }
    });
    STREAM_WRITE.with(|w| *w.borrow_mut() = Some((buffer, Vec::new())));
}

/// `trax.strw`: appends a word to the ray being written.
pub fn stream_write_word(word: u32) {
    let words = with_machine(|m| m.waits().streams.geometry().ray_words());
    STREAM_WRITE.with(|w| {
        if let Some((_, ray)) = w.borrow_mut().as_mut() {
            if ray.len() >= words {
                panic!(
                    "trax: ray too long: trax.strw past the end of a {}-byte ray record (stream_memory.ray_bytes)",
                    words * 4
                );
            }
            ray.push(word);
        }
    });
}

/// `trax.strwend`: pushes the ray onto its buffer; idle TMs schedule.
pub fn stream_write_end() {
    let Some((buffer, ray)) = STREAM_WRITE.with(|w| w.borrow_mut().take()) else {
        return;
    };
    with_machine(|m| {
        let mut b = m.waits();
        let Barriers { streams, sched, .. } = &mut *b;
        // Blocks spill and refill at once here (a host run is untimed): a write never
        // waits for the sentinel.
        match streams.push(buffer as usize, &ray) {
            Ok(_) => {}
            Err(streams::StreamError::Full(e)) => {
                drop(b);
                if e.capacity_rays == 0 {
                    panic!(
                        "trax: this chip has no ray stream memory (stream_memory.capacity_bytes = 0)"
                    );
                }
                panic!(
                    "trax: ray stream memory full: writing a ray to stream {}, but all {} slots of {}-byte rays are taken",
                    e.stream, e.capacity_rays, e.ray_bytes
                );
            }
            Err(streams::StreamError::SpillAreaFull(e)) => {
                drop(b);
                panic!(
                    "trax: ray spill area full: spilling a block of stream {}, but all {} blocks of {} bytes are taken (stream_memory.spill.area_bytes)",
                    e.stream, e.blocks, e.block_bytes
                );
            }
        }
        let before: u64 = sched.tms.iter().map(|t| t.generation).sum();
        sched.pushed(streams, 0);
        if sched.tms.iter().map(|t| t.generation).sum::<u64>() != before {
            m.barrier_cv.notify_all();
        }
    })
}

/// `trax.strrstart`: pops the newest ray of the TM's current buffer; 1 if there was one.
pub fn stream_read_start() -> u32 {
    let ray = with_machine(|m| {
        let mut b = m.waits();
        let cur = b.sched.tms[ids().tmid as usize].current;
        match b.streams.buffer(cur).map(|k| b.streams.pop(k)) {
            Some(streams::Popped::Ray(r)) => Some(r),
            // Untimed: a refill completes at once, so a read never waits.
            Some(streams::Popped::Wait) => unreachable!("host streams move blocks at once"),
            Some(streams::Popped::Empty) | None => None,
        }
    });
    let got = ray.is_some() as u32;
    STREAM_READ.with(|r| *r.borrow_mut() = ray.map(|v| (v, 0)));
    got
}

/// `trax.strr`: the next word of the ray being read (0 past its end or without one).
pub fn stream_read_word() -> u32 {
    STREAM_READ.with(|r| match r.borrow_mut().as_mut() {
        Some((ray, pos)) => {
            let v = ray.get(*pos).copied().unwrap_or(0);
            *pos += 1;
            v
        }
        None => 0,
    })
}

/// `trax.strrend`.
pub fn stream_read_end() {
    STREAM_READ.with(|r| *r.borrow_mut() = None);
}

/// `trax.strsize`: rays in buffer `buffer` (0 past the buffers).
pub fn stream_size(buffer: u32) -> u32 {
    with_machine(|m| {
        let b = m.waits();
        b.streams.buffer(buffer).map_or(0, |k| b.streams.len(k))
    })
}

/// `trax.strcap`: rays the stream memory holds.
pub fn stream_capacity() -> u32 {
    with_machine(|m| m.waits().streams.capacity_rays())
}

/// `trax.strsched`: waits until the TM has drained, then returns the buffer its stream
/// scheduler picked (0xFFFFFFFF when the frame's stream work is done).
pub fn stream_schedule() -> u32 {
    with_machine(|m| {
        let (tm, gid) = (ids().tmid as usize, ids().gid as usize);
        let mut b = m.waits();
        let live = b.live;
        let Barriers { streams, sched, .. } = &mut *b;
        let generation = sched.arrive(tm, streams, live, 0);
        if sched.released(tm, generation, u64::MAX) {
            m.barrier_cv.notify_all();
            return sched.tms[tm].current;
        }
        b.waits[gid] = Wait::Schedule;
        let mut b = m.wait_until(b, |b| b.sched.released(tm, generation, u64::MAX));
        b.waits[gid] = Wait::None;
        b.sched.tms[tm].current
    })
}

// ---- Statistics ----

/// Counts one ray (per thread; summed when the thread finishes).
pub fn count_ray() {
    stat_add(0, 1);
}

/// Statistics counter `counter` += `n` (per thread; summed when the thread finishes); a
/// counter past the last panics, as `trax.statadd` faults on the machine.
pub fn stat_add(counter: u32, n: u32) {
    if counter as usize >= counters::NUM_STATS {
        panic!(
            "statistics counter index {counter} out of range (0..{})",
            counters::NUM_STATS
        );
    }
    STATS.with(|s| {
        let mut c = s.get();
        c[counter as usize] += u64::from(n);
        s.set(c);
    });
}

// ---- Simulated memory ----

pub fn load_u32(addr: u32) -> u32 {
    with_machine(|m| m.word(addr, "load").load(Ordering::Relaxed))
}

pub fn load_f32(addr: u32) -> f32 {
    f32::from_bits(load_u32(addr))
}

pub fn store_u32(addr: u32, v: u32) {
    with_machine(|m| m.word_mut(addr).store(v, Ordering::Relaxed))
}

pub fn store_f32(addr: u32, v: f32) {
    store_u32(addr, v.to_bits())
}

// ---- Scene header fields, generated from abi::SceneHeader (prelude::render_header_fields) ----

pub fn hdr_magic() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_MAGIC
}

pub fn hdr_version() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_VERSION
}

pub fn hdr_width() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_WIDTH
}

pub fn hdr_height() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_HEIGHT
}

pub fn hdr_inv_width() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_INV_WIDTH
}

pub fn hdr_inv_height() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_INV_HEIGHT
}

pub fn hdr_spp() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_SPP
}

pub fn hdr_max_depth() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_MAX_DEPTH
}

pub fn hdr_epsilon() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_EPSILON
}

pub fn hdr_seed() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_SEED
}

pub fn hdr_background() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_BACKGROUND
}

pub fn hdr_camera() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_CAMERA
}

pub fn hdr_framebuffer() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_FRAMEBUFFER
}

pub fn hdr_bvh_nodes() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_BVH_NODES
}

pub fn hdr_triangles() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_TRIANGLES
}

pub fn hdr_normals() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_NORMALS
}

pub fn hdr_texcoords() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_TEXCOORDS
}

pub fn hdr_material_ids() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_MATERIAL_IDS
}

pub fn hdr_materials() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_MATERIALS
}

pub fn hdr_emitters() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_EMITTERS
}

pub fn hdr_point_lights() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_POINT_LIGHTS
}

pub fn hdr_bvh_parents() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_BVH_PARENTS
}

pub fn hdr_treelet_ids() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_TREELET_IDS
}

pub fn hdr_tri_treelet_ids() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_TRI_TREELET_IDS
}

pub fn hdr_tri_leaf_ids() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_TRI_LEAF_IDS
}

pub fn hdr_stream_rays() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_STREAM_RAYS
}

pub fn hdr_stream_ray_bytes() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_STREAM_RAY_BYTES
}

pub fn hdr_stream_buffers() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_STREAM_BUFFERS
}

pub fn hdr_pipe_modes() -> u32 {
    layout::SCENE_HEADER_ADDR + layout::HDR_PIPE_MODES
}

// ---- end of the scene header fields ----

// ---- The host runner ----

/// A memory image (the runtime's one image type, compiled into this crate).
pub type Image = image::MemoryImage;

/// Parses a memory image file's bytes.
pub fn parse_image(data: &[u8]) -> Result<Image, String> {
    image::MemoryImage::parse(data).map_err(|e| e.to_string())
}

/// Serialises a memory image.
pub fn image_bytes(image: &Image) -> Vec<u8> {
    image.to_bytes()
}

fn build_machine(
    image: &Image,
    num_tms: u32,
    threads_per_tm: u32,
    schedule: &str,
    spill: Option<&str>,
) -> Result<Machine, String> {
    let spill = match spill {
        None => None,
        Some(a) => Some(streams::SpillGeometry::from_arg(a).ok_or_else(|| {
            format!(
                "bad spill sentinel `{a}` (expected HIGH,LOW,BLOCK_RAYS,BLOCK_BYTES,AREA_BLOCKS)"
            )
        })?),
    };
    let policy = streams::SchedulePolicy::from_name(schedule).ok_or_else(|| {
        let names: Vec<&str> = streams::SchedulePolicy::ALL
            .iter()
            .map(|(_, n)| *n)
            .collect();
        format!(
            "unknown stream schedule policy `{schedule}` (expected one of {})",
            names.join(", ")
        )
    })?;
    image.validate().map_err(|e| e.to_string())?;
    let mut segments: Vec<image::Segment> = image
        .segments
        .iter()
        .filter(|s| s.size > 0)
        .cloned()
        .collect();
    segments.sort_by_key(|s| s.addr);
    if let Some(s) = segments
        .first()
        .filter(|s| s.addr < layout::SCENE_HEADER_ADDR)
    {
        return Err(format!(
            "memory image segment `{}` at {:#010x} overlaps the null guard",
            s.name, s.addr
        ));
    }
    // Word-granular span covering every segment.
    let base = segments
        .first()
        .map(|s| s.addr & !3)
        .unwrap_or(layout::SCENE_HEADER_ADDR);
    let end = segments
        .iter()
        .map(|s| s.end().next_multiple_of(4))
        .max()
        .unwrap_or(base as u64);
    if end - base as u64 > MAX_SPAN_BYTES {
        return Err(format!(
            "memory image spans {:#x} bytes ({:#010x}..{end:#x}); the host runner maps at most {MAX_SPAN_BYTES:#x}",
            end - base as u64,
            base
        ));
    }
    let mut mem: Vec<AtomicU32> = Vec::with_capacity(((end - base as u64) / 4) as usize);
    mem.resize_with(((end - base as u64) / 4) as usize, || AtomicU32::new(0));
    for s in &segments {
        for (k, &byte) in s.data.iter().enumerate() {
            let at = (s.addr - base) as usize + k;
            let w = mem[at / 4].get_mut();
            let shift = 8 * (at % 4);
            *w = (*w & !(0xff << shift)) | (byte as u32) << shift;
        }
    }
    let writable = segments
        .iter()
        .filter(|s| s.perms.write())
        .map(|s| (s.addr as u64, s.end()))
        .collect();
    let threads = num_tms
        .checked_mul(threads_per_tm)
        .filter(|&n| n > 0 && n <= 4096)
        .ok_or_else(|| {
            format!("bad thread count {num_tms} TMs x {threads_per_tm} threads (1..=4096 in all)")
        })?;
    let mut m = Machine {
        base,
        mem,
        segments,
        writable,
        globals: (0..NUM_GLOBAL_REGS).map(|_| AtomicU32::new(0)).collect(),
        barriers: Mutex::new(Barriers {
            live: threads,
            arrived: vec![0; NUM_GLOBAL_REGS as usize],
            generation: vec![0; NUM_GLOBAL_REGS as usize],
            streams: streams::StreamMemory::new(streams::StreamGeometry {
                capacity_bytes: 0,
                ..Default::default()
            }),
            sched: streams::StreamScheduler::new(num_tms, threads_per_tm, policy, 0),
            waits: vec![Wait::None; threads as usize],
            aborted: false,
        }),
        barrier_cv: Condvar::new(),
        num_tms,
        threads_per_tm,
        seed: 0,
        start: Instant::now(),
        stats: std::array::from_fn(|_| AtomicU64::new(0)),
        pipe_modes: (0..num_tms).map(|_| AtomicU32::new(0)).collect(),
    };
    // The random streams' seed comes from the header when the image has one.
    let seed_addr = layout::SCENE_HEADER_ADDR + layout::HDR_SEED;
    if m.segments.iter().any(|s| s.holds(seed_addr, 4)) {
        m.seed = m.word(seed_addr, "load").load(Ordering::Relaxed);
    }
    // The ray stream memory's shape, as the chip config put it in the header.
    let field = |off: u32| {
        let addr = layout::SCENE_HEADER_ADDR + off;
        if m.segments.iter().any(|s| s.holds(addr, 4)) {
            m.word(addr, "load").load(Ordering::Relaxed)
        } else {
            0
        }
    };
    let (rays, ray_bytes, buffers) = (
        field(layout::HDR_STREAM_RAYS),
        field(layout::HDR_STREAM_RAY_BYTES),
        field(layout::HDR_STREAM_BUFFERS),
    );
    if field(layout::HDR_MAGIC) == layout::SCENE_MAGIC
        && field(layout::HDR_VERSION) == layout::SCENE_VERSION
        && rays > 0
    {
        if ray_bytes == 0 || ray_bytes % 4 != 0 || buffers == 0 {
            return Err(format!(
                "scene header: bad stream memory shape ({rays} rays of {ray_bytes} bytes in {buffers} buffers)"
            ));
        }
        m.barriers
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .streams = streams::StreamMemory::with_capacity_rays(rays, ray_bytes, buffers, spill);
    }
    Ok(m)
}

/// Why a host run failed.
#[derive(Debug)]
pub enum RunError {
    /// The image or configuration is unusable.
    Setup(String),
    /// Kernel threads panicked: their global ids.
    Panicked(Vec<u32>),
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Setup(s) => write!(f, "{s}"),
            RunError::Panicked(ids) => write!(f, "kernel panicked in thread(s) {ids:?}"),
        }
    }
}

/// Figures of a host run.
#[derive(Clone, Copy, Debug)]
pub struct RunStats {
    /// Rays counted with `count_ray` by all threads (counter 0).
    pub rays: u64,
    /// Every statistics counter, summed over all threads (`trax::stat`).
    pub counters: [u64; counters::NUM_STATS],
    /// Wall-clock seconds of the kernel threads.
    pub seconds: f64,
}

/// Runs `kernel` on `num_tms × threads_per_tm` host threads over `image` and returns the
/// final memory as an image (same non-empty segments, current contents).
pub fn run_image(
    image: &Image,
    num_tms: u32,
    threads_per_tm: u32,
    kernel: fn(),
) -> Result<Image, RunError> {
    run_image_stats(image, num_tms, threads_per_tm, kernel).map(|(img, _)| img)
}

/// [`run_image`], also returning the run's figures.
pub fn run_image_stats(
    image: &Image,
    num_tms: u32,
    threads_per_tm: u32,
    kernel: fn(),
) -> Result<(Image, RunStats), RunError> {
    run_image_with(image, num_tms, threads_per_tm, "fullest", None, kernel)
}

/// [`run_image_stats`] with the ray stream schedulers' policy (`stream_memory.schedule`
/// of the chip config: `fullest`, `sticky`, `round-robin` or `claimed`) and, when the chip's stream
/// memory spills (`stream_memory.overflow = "spill"`), its sentinel's shape in
/// `SpillGeometry::to_arg`'s form (blocks move at once, as in a functional run).
pub fn run_image_with(
    image: &Image,
    num_tms: u32,
    threads_per_tm: u32,
    schedule: &str,
    spill: Option<&str>,
    kernel: fn(),
) -> Result<(Image, RunStats), RunError> {
    let machine = Arc::new(
        build_machine(image, num_tms, threads_per_tm, schedule, spill).map_err(RunError::Setup)?,
    );
    let mut failed = Vec::new();
    std::thread::scope(|scope| {
        let mut handles = Vec::new();
        for gid in 0..machine.num_threads() {
            let m = Arc::clone(&machine);
            let builder = std::thread::Builder::new()
                .name(format!(
                    "trax-tm{}-t{}",
                    gid / threads_per_tm,
                    gid % threads_per_tm
                ))
                .stack_size(KERNEL_STACK_BYTES);
            let h = builder.spawn_scoped(scope, move || {
                MACHINE.with(|c| c.set(Arc::as_ptr(&m)));
                let _live = LiveGuard(m);
                IDS.with(|c| {
                    c.set(Ids {
                        tid: gid % threads_per_tm,
                        tmid: gid / threads_per_tm,
                        gid,
                    })
                });
                RNG.with(|c| c.set(None));
                kernel();
            });
            match h {
                Ok(h) => handles.push((gid, h)),
                Err(e) => {
                    eprintln!("trax: cannot start kernel thread {gid}: {e}");
                    failed.push(gid);
                    // The thread never ran: it is not live.
                    machine.thread_gone(gid / threads_per_tm);
                }
            }
        }
        for (gid, h) in handles {
            if h.join().is_err() {
                failed.push(gid);
            }
        }
    });
    if !failed.is_empty() {
        failed.sort();
        return Err(RunError::Panicked(failed));
    }
    let counters = std::array::from_fn(|i| machine.stats[i].load(Ordering::Relaxed));
    let stats = RunStats {
        rays: counters[0],
        counters,
        seconds: machine.start.elapsed().as_secs_f64(),
    };
    let segments = machine
        .segments
        .iter()
        .map(|s| {
            let first = ((s.addr - machine.base) / 4) as usize;
            let last = ((s.end().next_multiple_of(4) - machine.base as u64) / 4) as usize;
            let words: Vec<u8> = machine.mem[first..last]
                .iter()
                .flat_map(|w| w.load(Ordering::Relaxed).to_le_bytes())
                .collect();
            let skip = (s.addr & 3) as usize;
            image::Segment {
                data: words[skip..skip + s.size as usize].to_vec(),
                ..s.clone()
            }
        })
        .collect();
    Ok((image::MemoryImage { segments }, stats))
}

/// Marks its thread as finished (even on panic) so barriers stop waiting for it.
struct LiveGuard(Arc<Machine>);

impl Drop for LiveGuard {
    fn drop(&mut self) {
        MACHINE.with(|c| c.set(std::ptr::null()));
        let m = &self.0;
        for (total, n) in m
            .stats
            .iter()
            .zip(STATS.with(|s| s.replace([0; counters::NUM_STATS])))
        {
            total.fetch_add(n, Ordering::Relaxed);
        }
        if std::thread::panicking() {
            m.waits().aborted = true;
        }
        m.thread_gone(ids().tmid);
    }
}

impl Machine {
    /// A kernel thread of TM `tm` finished (or never started): one live thread less for
    /// barriers and its TM's stream scheduler; waiting threads look again (a release, or a
    /// deadlock they must report).
    fn thread_gone(&self, tm: u32) {
        let mut b = self.waits();
        b.live -= 1;
        self.release_complete_barriers(&mut b);
        let live = b.live;
        let Barriers { streams, sched, .. } = &mut *b;
        sched.halted(tm as usize, streams, live, 0);
        self.barrier_cv.notify_all();
    }
}

/// Entry point of a natively built kernel: `PROGRAM IMAGE_IN FRAMEBUFFER_OUT TMS THREADS
/// [SCHEDULE [SPILL]]` (SCHEDULE: the ray stream schedulers' policy, default `fullest`;
/// SPILL: the stream memory's spill sentinel, `HIGH,LOW,BLOCK_RAYS,BLOCK_BYTES,AREA_BLOCKS`).
///
/// Runs the kernel over the memory image and writes the framebuffer (header field
/// `framebuffer`, `count × layout::PIXEL_SIZE` bytes) as a one-segment memory image. Exits with status 1
/// (after the panic message) if any kernel thread panics, 2 on a usage or I/O error.
pub fn host_main(kernel: fn()) {
    let args: Vec<String> = std::env::args().collect();
    if !(5..=7).contains(&args.len()) {
        eprintln!(
            "usage: {} IMAGE_IN FRAMEBUFFER_OUT TMS THREADS [SCHEDULE [SPILL]]",
            args[0]
        );
        std::process::exit(2);
    }
    let schedule = args.get(5).map_or("fullest", String::as_str);
    let spill = args.get(6).map(String::as_str);
    let fail = |msg: String| -> ! {
        eprintln!("trax native: {msg}");
        std::process::exit(2)
    };
    let data = std::fs::read(&args[1]).unwrap_or_else(|e| fail(format!("{}: {e}", args[1])));
    let image = parse_image(&data).unwrap_or_else(|e| fail(format!("{}: {e}", args[1])));
    let tms: u32 = args[3]
        .parse()
        .unwrap_or_else(|_| fail(format!("bad TMS {:?}", args[3])));
    let threads: u32 = args[4]
        .parse()
        .unwrap_or_else(|_| fail(format!("bad THREADS {:?}", args[4])));
    // A panicking kernel thread ends the whole program, as on the simulated machine
    // (other threads may be waiting on it forever).
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        default_hook(info);
        std::process::exit(1);
    }));
    let out = match run_image_with(&image, tms, threads, schedule, spill, kernel) {
        Ok((out, stats)) => {
            let mut line = format!(
                "trax native: {} threads, {:.3} s",
                tms * threads,
                stats.seconds
            );
            if stats.rays > 0 {
                line += &format!(
                    ", {} rays ({:.2} M rays/s)",
                    stats.rays,
                    stats.rays as f64 / stats.seconds.max(1e-9) / 1e6
                );
            }
            eprintln!("{line}");
            if let Some(line) = counters::summary(&stats.counters) {
                eprintln!("{line}");
            }
            out
        }
        Err(RunError::Setup(e)) => fail(e),
        Err(e) => {
            eprintln!("trax native: {e}");
            std::process::exit(1);
        }
    };
    let fb = framebuffer_segment(&out);
    if let Err(e) = std::fs::write(&args[2], fb.to_bytes()) {
        fail(format!("{}: {e}", args[2]));
    }
}

/// The framebuffer region of a memory image, per its scene header (empty if none).
pub fn framebuffer_segment(image: &Image) -> Image {
    let word = |addr: u32| image.read_u32(addr);
    let field = layout::SCENE_HEADER_ADDR + layout::HDR_FRAMEBUFFER;
    let (Some(addr), Some(count)) = (
        word(field + layout::COMPONENT_ADDR),
        word(field + layout::COMPONENT_COUNT),
    ) else {
        return Image::default();
    };
    let bytes = count
        .checked_mul(layout::FRAMEBUFFER_STRIDE)
        .and_then(|len| image.read(addr, len));
    match bytes {
        Some(data) if count > 0 => Image {
            segments: vec![image::Segment::new(
                "framebuffer",
                addr,
                data,
                image::Perms::RW,
            )],
        },
        _ => Image::default(),
    }
}
