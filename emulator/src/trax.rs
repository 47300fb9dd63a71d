//! Functional semantics of the TRaX extension instructions (`trax_runtime::isa`).
//!
//! Choices documented here:
//! - Global registers: `G[0..NUM_GLOBALS)`; an index outside is a fault.
//! - `trax.barrier rs`: `G[rs]` counts arrivals; when it reaches the number of live
//!   (not halted) threads it is reset to 0 and every waiting thread is released. A thread
//!   halting while others wait re-checks the condition.
//! - `trax.semacq`: if `G[rs] == 0` the thread retries on its next turn (no progress is
//!   made, so a program where every thread waits is reported as a deadlock).
//! - `trax.clock`: the thread's retired-instruction count in functional mode.
//! - `trax.rand`: `trax_runtime::rng::Rng` seeded from the scene header seed and the
//!   thread's global id (identical to `trax native`); `trax.seed rs, rt` replaces it with
//!   the stream of pixel `rs`, sample `rt` (`Rng::for_sample`, independent of the thread).
//! - `trax.fmin/fmax/invsqrt`: `trax_runtime::fops`; `trax.boxtest/tritest`:
//!   `trax_runtime::pipes` (both identical to `trax native`).
//! - Streams: the ray stream memory of `crate::streams` (fixed capacity, LIFO buffers;
//!   a write to a full memory and `trax.strw` past a ray record are faults).
//!   `trax.strrstart` pops from the TM's current buffer. `trax.strsched` is a wait
//!   (`RunState::StreamWait`): the thread resumes when its TM's stream scheduler has
//!   drained the TM (every live thread of the TM in `trax.strsched`) and picked the next
//!   buffer by `stream_memory.schedule`, with that buffer's id; when every buffer stays
//!   empty until every live thread of the chip waits there, all resume with 0xFFFFFFFF.
//!   A write wakes the idle TMs (drained, nothing to read), which then schedule.
//! - `trax.setpipe`: modes 0 (general), 1 (box pipeline), 2 (triangle pipeline); another
//!   value is a fault. `trax.boxtest` needs mode 1 and `trax.tritest` mode 2 (a fault
//!   otherwise), on the host as on the machine. A `trax.setpipe` to the mode the TM is in
//!   does nothing (timing: an ordinary one-cycle instruction, no chip-wide ordering and no
//!   reconfiguration); one that changes it is chip-wide state, executed in order with
//!   the other TMs' chip-wide instructions. In timing mode the TM's units follow the new
//!   mode from its next quantum: pipeline tests already issued keep their results and
//!   latency, tests issued before then by other threads of the TM still see the old mode
//!   (functional mode, which has no quanta, checks each test against the mode at that
//!   point of the interleaving), and the FP units and the pipeline are unavailable for
//!   `pipelines.reconfig_cycles` from the quantum's start.
//! - Box pipeline: slab test with the ray's inverse direction; NaN slab distances (0 * inf)
//!   are ignored; returns the entry distance `max(tmin, 0)` when `tmax >= max(tmin, 0)`,
//!   else +inf. Triangle pipeline: the Plücker-coordinate test of `pipes::tri_test`
//!   (hits with `t > 0`, edges inside); barycentrics go to cop2 21 and 22.

use crate::chip::Chip;
use crate::streams;
use crate::thread::{Fault, RunState, Thread, NUM_GLOBALS, NUM_STATS};
use std::fmt::Write as _;
use trax_runtime::isa::{AbortKind, TraxOp};
use trax_runtime::{abortmsg, fops, pipes};

/// What the scheduler does after a TRaX instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraxFlow {
    /// Continue.
    Next,
    /// The thread halted.
    Halt,
    /// The thread waits (barrier, `trax.strsched`).
    Block,
    /// Not executed; try again later (pc unchanged).
    Retry,
    /// Not executed: it changes chip-wide state the [`Chip`] view may not change.
    Defer,
}

fn greg(index: u32) -> Result<usize, Fault> {
    if (index as usize) < NUM_GLOBALS {
        Ok(index as usize)
    } else {
        Err(Fault::BadIndex {
            what: "global register",
            index,
        })
    }
}

/// Renders a formatted message (a panic's or a print's) from its argument record at
/// `addr` (`len` bytes):
/// template address and length, then 8-byte argument slots (see `abortmsg`).
fn abort_record(mem: &crate::memory::Memory, local: &[u8], addr: u32, len: u32) -> String {
    let unreadable = || format!("<unreadable panic message record at {addr:#010x}>");
    let max = 8 + 8 * abortmsg::MAX_ARGS;
    let Ok(rec) = mem.read_bytes(local, addr, len.min(max)) else {
        return unreadable();
    };
    if rec.len() < 8 {
        return unreadable();
    }
    let word = |i: usize| u32::from_le_bytes([rec[i], rec[i + 1], rec[i + 2], rec[i + 3]]);
    let (tpl_addr, tpl_len) = (word(0), word(4).min(abortmsg::MAX_TEXT));
    let args: Vec<u64> = rec[8..]
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect();
    let Ok(template) = mem.read_bytes(local, tpl_addr, tpl_len) else {
        return format!("<unreadable panic message at {tpl_addr:#010x}>");
    };
    abortmsg::render(&template, &args, |a, l| mem.read_bytes(local, a, l).ok())
}

fn mem_err(f: crate::memory::MemFault) -> Fault {
    Fault::Memory {
        fault: f,
        fetch: false,
    }
}

/// Executes one TRaX instruction.
#[inline(never)]
pub fn exec_trax<C: Chip>(
    t: &mut Thread,
    chip: &mut C,
    op: TraxOp,
    rd: u8,
    rs: u8,
    rt: u8,
    sa: u8,
) -> Result<TraxFlow, Fault> {
    use TraxOp::*;
    let g = |r: u8| t.regs.gpr[(r & 31) as usize];
    let (vs, vt) = (g(rs), g(rt));
    let f32s = f32::from_bits(t.regs.f32_bits((rs & 31) as usize));
    let f32t = f32::from_bits(t.regs.f32_bits((rt & 31) as usize));
    let rd = (rd & 31) as usize;
    let set = |t: &mut Thread, v: u32| {
        if rd != 0 {
            t.regs.gpr[rd] = v;
        }
    };
    // Operations that change chip-wide state need exclusive access (and count as a
    // change, `Shared::changes`).
    macro_rules! exclusive {
        () => {
            match chip.exclusive() {
                Some(sh) => {
                    sh.changes += 1;
                    sh
                }
                None => return Ok(TraxFlow::Defer),
            }
        };
    }
    match op {
        ThreadId => set(t, t.tid),
        TmId => set(t, t.tm),
        GlobalId => set(t, t.gid),
        NumThreads => set(t, chip.shared().shape.total()),
        NumTms => set(t, chip.shared().shape.tms),
        Clock => set(t, t.retired as u32),
        Rand => {
            let v = t.rng.next_f32();
            t.regs.set_f32_bits(rd, v.to_bits());
        }
        Seed => t.rng.reseed(vs, vt),
        Halt => {
            t.state = RunState::Halted;
            return Ok(TraxFlow::Halt);
        }
        AtomicInc | AtomicDec | AtomicAdd | IncReset => {
            let i = greg(vs)?;
            let sh = exclusive!();
            let old = sh.globals[i];
            sh.globals[i] = match op {
                AtomicInc => old.wrapping_add(1),
                AtomicDec => old.wrapping_sub(1),
                AtomicAdd => old.wrapping_add(vt),
                _ => {
                    let n = old.wrapping_add(1);
                    if n >= sh.shape.total() {
                        0
                    } else {
                        n
                    }
                }
            };
            set(t, old);
        }
        GlobalRead => {
            let v = chip.shared().globals[greg(vs)?];
            set(t, v);
        }
        GlobalWrite => {
            let i = greg(vs)?;
            exclusive!().globals[i] = vt;
        }
        Barrier => {
            let i = greg(vs)?;
            let sh = exclusive!();
            sh.globals[i] = sh.globals[i].wrapping_add(1);
            if sh.globals[i] >= sh.live_threads {
                sh.globals[i] = 0;
                sh.barrier_generation[i] += 1;
                sh.barrier_waiting[i] = 0;
            } else {
                sh.barrier_waiting[i] += 1;
                t.state = RunState::Barrier {
                    reg: i as u32,
                    generation: sh.barrier_generation[i],
                };
                return Ok(TraxFlow::Block);
            }
        }
        SemAcquire => {
            let i = greg(vs)?;
            let sh = exclusive!();
            if sh.globals[i] == 0 {
                // Nothing changed: the thread tries again.
                sh.changes -= 1;
                return Ok(TraxFlow::Retry);
            }
            sh.globals[i] -= 1;
        }
        SemRelease => {
            let i = greg(vs)?;
            let sh = exclusive!();
            sh.globals[i] = sh.globals[i].wrapping_add(1);
        }
        FMin => t.regs.set_f32_bits(rd, fops::fmin(f32s, f32t).to_bits()),
        FMax => t.regs.set_f32_bits(rd, fops::fmax(f32s, f32t).to_bits()),
        InvSqrt => t.regs.set_f32_bits(rd, fops::invsqrt(f32s).to_bits()),
        PrintInt => {
            let _ = write!(Out(chip.output()), "{}", vs as i32);
        }
        PrintUint => {
            let _ = write!(Out(chip.output()), "{vs}");
        }
        PrintF32 => {
            let _ = write!(Out(chip.output()), "{f32s}");
        }
        PrintF64 => {
            let v = f64::from_bits(t.regs.f64_bits((rs & 31) as usize));
            let _ = write!(Out(chip.output()), "{v}");
        }
        PrintStr => {
            let bytes = chip
                .shared()
                .mem
                .read_bytes(&t.local, vs, vt)
                .map_err(mem_err)?;
            chip.output()
                .extend_from_slice(String::from_utf8_lossy(&bytes).as_bytes());
        }
        PrintChar => {
            let c = char::from_u32(vs).unwrap_or(char::REPLACEMENT_CHARACTER);
            let _ = write!(Out(chip.output()), "{c}");
        }
        PrintBool => {
            let _ = write!(Out(chip.output()), "{}", vs != 0);
        }
        PrintI64 => {
            let v = ((vt as u64) << 32 | vs as u64) as i64;
            let _ = write!(Out(chip.output()), "{v}");
        }
        PrintFmt => {
            let text = abort_record(&chip.shared().mem, &t.local, vs, vt);
            chip.output().extend_from_slice(text.as_bytes());
        }
        PrintU64 => {
            let v = (vt as u64) << 32 | vs as u64;
            let _ = write!(Out(chip.output()), "{v}");
        }
        Abort => {
            let mem = &chip.shared().mem;
            let message = if vs & abortmsg::ABORT_FORMATTED != 0 {
                abort_record(mem, &t.local, vt, g(rd as u8))
            } else {
                let len = g(rd as u8).min(abortmsg::MAX_TEXT);
                match mem.read_bytes(&t.local, vt, len) {
                    Ok(b) => String::from_utf8_lossy(&b).into_owned(),
                    Err(_) => format!("<unreadable message at {vt:#010x}>"),
                }
            };
            return Err(Fault::Abort {
                kind: AbortKind::from_code(vs),
                code: vs & !abortmsg::ABORT_FORMATTED,
                message,
            });
        }
        ProfBegin => t.profile_open.push((sa, t.retired)),
        ProfEnd => {
            if let Some(p) = t.profile_open.iter().rposition(|(r, _)| *r == sa) {
                let (_, start) = t.profile_open.remove(p);
                chip.profile()[(sa & 31) as usize] += t.retired - start;
            }
        }
        Stat => {
            let i = sa as usize;
            if i >= NUM_STATS {
                return Err(Fault::BadIndex {
                    what: "statistics counter",
                    index: sa as u32,
                });
            }
            chip.stats()[i] += 1;
        }
        StatAdd => {
            let i = vs as usize;
            if i >= NUM_STATS {
                return Err(Fault::BadIndex {
                    what: "statistics counter",
                    index: vs,
                });
            }
            chip.stats()[i] += u64::from(vt);
        }
        StreamWriteStart => {
            streams::buffer(&chip.shared().streams, vs)?;
            t.stream_write = Some((vs, Vec::new()));
        }
        StreamWrite => {
            let geom = *chip.shared().streams.geometry();
            if let Some((_, w)) = &mut t.stream_write {
                if w.len() >= geom.ray_words() {
                    return Err(Fault::RayTooLong {
                        ray_bytes: geom.ray_bytes,
                    });
                }
                w.push(vs);
            }
        }
        StreamWriteEnd => {
            if t.stream_write.is_some() {
                let sh = exclusive!();
                if let Some((id, words)) = t.stream_write.take() {
                    let b = streams::buffer(&sh.streams, id)?;
                    if streams::push(&mut sh.streams, b, &words)? == streams::Flow::Wait {
                        // The spill sentinel is making room: retry (the record is kept).
                        t.stream_write = Some((id, words));
                        return Ok(TraxFlow::Retry);
                    }
                    sh.sched.pushed(&sh.streams, sh.clock);
                }
            }
        }
        StreamReadStart => {
            let sh = exclusive!();
            let cur = sh.sched.tms[t.tm as usize].current;
            let ray = match sh.streams.buffer(cur).map(|b| sh.streams.pop(b)) {
                Some(streams::Popped::Ray(r)) => Some(r),
                // The buffer's rays are on their way back from DRAM: retry.
                Some(streams::Popped::Wait) => return Ok(TraxFlow::Retry),
                _ => None,
            };
            let got = ray.is_some();
            t.stream_read = ray.map(|r| (r, 0));
            set(t, got as u32);
        }
        StreamRead => {
            let v = match &mut t.stream_read {
                Some((w, pos)) => {
                    let v = w.get(*pos).copied().unwrap_or(0);
                    *pos += 1;
                    v
                }
                None => 0,
            };
            set(t, v);
        }
        StreamReadEnd => t.stream_read = None,
        StreamSize => {
            let streams = &chip.shared().streams;
            let n = streams.buffer(vs).map_or(0, |b| streams.len(b));
            set(t, n);
        }
        StreamSchedule => {
            let generation = exclusive!().stream_arrive(t.tm);
            t.state = RunState::StreamWait {
                rd: rd as u8,
                generation,
            };
            return Ok(TraxFlow::Block);
        }
        StreamCapacity => {
            let n = chip.shared().streams.capacity_rays();
            set(t, n);
        }
        SetPipe => {
            if sa > 2 {
                return Err(Fault::BadIndex {
                    what: "pipeline mode",
                    index: sa as u32,
                });
            }
            if chip.shared().pipe_modes & (1 << sa) == 0 {
                return Err(Fault::BadIndex {
                    what: "pipeline mode (pipelines disabled, or the TM lacks the FP units it reserves)",
                    index: sa as u32,
                });
            }
            // Asking for the current mode is free (a TM asks on every schedule).
            if chip.shared().tm_pipe_mode[t.tm as usize] != sa {
                exclusive!().tm_pipe_mode[t.tm as usize] = sa;
            }
        }
        BoxTest => {
            need_mode(chip.shared().tm_pipe_mode[t.tm as usize], 1, "trax.boxtest")?;
            let c = |i: usize| f32::from_bits(t.cop2[i]);
            let r = pipes::box_test(
                [c(0), c(1), c(2)],
                [c(3), c(4), c(5)],
                [c(6), c(7), c(8)],
                [c(9), c(10), c(11)],
            );
            t.regs.set_f32_bits(rd, r.to_bits());
        }
        TriTest => {
            need_mode(chip.shared().tm_pipe_mode[t.tm as usize], 2, "trax.tritest")?;
            let c = |i: usize| f32::from_bits(t.cop2[i]);
            let (r, u, v) = pipes::tri_test(
                [c(0), c(1), c(2)],
                [c(3), c(4), c(5)],
                [c(12), c(13), c(14)],
                [c(15), c(16), c(17)],
                [c(18), c(19), c(20)],
            );
            t.cop2[21] = u.to_bits();
            t.cop2[22] = v.to_bits();
            t.regs.set_f32_bits(rd, r.to_bits());
        }
    }
    Ok(TraxFlow::Next)
}

/// A fused-pipeline instruction runs only in its `trax.setpipe` mode.
fn need_mode(mode: u8, needed: u8, instr: &'static str) -> Result<(), Fault> {
    if mode == needed {
        Ok(())
    } else {
        Err(Fault::PipeMode {
            instr,
            mode,
            needed,
        })
    }
}

/// `fmt::Write` adapter over the output buffer.
struct Out<'a>(&'a mut Vec<u8>);
impl std::fmt::Write for Out<'_> {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.0.extend_from_slice(s.as_bytes());
        Ok(())
    }
}
