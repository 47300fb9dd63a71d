//! Human-readable crash reports: what went wrong, where (thread, TM, instruction count,
//! PC, disassembly), the source location with its inline chain, a backtrace from the
//! shadow call stack, and the source line.

use std::fmt::Write as _;

use crate::debuginfo::{DebugInfo, SourceFrame};
use crate::elf::Executable;
use crate::machine::Crash;
use crate::memory::SegmentInfo;
use crate::thread::{Fault, Shared};

/// The segment whose permissions a memory fault broke (a store to read-only memory, a load
/// from non-readable or a fetch from non-executable memory).
fn denied_segment<'a>(crash: &Crash, sh: &'a Shared) -> Option<&'a SegmentInfo> {
    use crate::memory::MemFaultKind::{NotExecutable, NotReadable, ReadOnly};
    match &crash.fault {
        Fault::Memory { fault, .. }
            if matches!(fault.kind, ReadOnly | NotReadable | NotExecutable) =>
        {
            sh.mem.segment_at(fault.addr)
        }
        _ => None,
    }
}

/// Formats the report of `crash`. `exe` supplies symbols, `dbg` source locations.
pub fn report(
    crash: &Crash,
    sh: &Shared,
    exe: Option<&Executable>,
    dbg: Option<&DebugInfo>,
) -> String {
    let mut s = String::new();
    let when = match crash.cycle {
        Some(c) => format!("at cycle {c}, after {} instructions", crash.retired),
        None => format!("after {} instructions", crash.retired),
    };
    let _ = writeln!(
        s,
        "error: thread {} (TM {}, thread {}) crashed {when}",
        crash.gid, crash.tm, crash.tid
    );
    // A multi-line panic message (assert_eq!'s left/right) stays in the message column.
    let what = crash.fault.to_string().replace('\n', "\n        ");
    let _ = writeln!(s, "  what: {what}");
    if let Some(seg) = denied_segment(crash, sh) {
        let _ = writeln!(
            s,
            "  in:   segment `{}` ({:#010x}..{:#010x}, {})",
            seg.name,
            seg.addr,
            seg.addr as u64 + seg.size as u64,
            seg.perms
        );
    }
    let dis = sh
        .program
        .get(crash.pc)
        .copied()
        .or_else(|| sh.mem.peek_u32(crash.pc).map(crate::decode::decode))
        .map(|i| i.to_string().replace('\t', " "))
        .unwrap_or_else(|| "<no instruction>".into());
    let slot = if crash.in_slot {
        "  (in a delay/forbidden slot)"
    } else {
        ""
    };
    let sym = exe
        .and_then(|e| e.symbol_at(crash.pc))
        .map(|(s, off)| format!(" <{}+{:#x}>", demangle(&s.name), off))
        .unwrap_or_default();
    let _ = writeln!(s, "  pc:   {:#010x}{sym}: {dis}{slot}", crash.pc);
    let frames = dbg.map(|d| d.frames(crash.pc));
    if let Some(frames) = frames.as_deref().filter(|f| !f.is_empty()) {
        let f0 = &frames[0];
        let _ = write!(s, "  at:   {} in {}", f0.location(), fname(f0));
        for w in frames.windows(2) {
            let _ = write!(
                s,
                ", inlined into {} at {}",
                fname(&w[1]),
                w[0].call_site_hint(&w[1])
            );
        }
        let _ = writeln!(s);
        if let (Some(file), Some(d)) = (&f0.file, dbg) {
            if let Some(line) = d.source_line(file, f0.line) {
                let _ = writeln!(s, "  {:>5} | {}", f0.line, line.trim_end());
            }
        }
    } else if dbg.is_some_and(|d| !d.has_dwarf()) {
        let _ = writeln!(
            s,
            "  (no debug information: build with -g for source locations)"
        );
    } else if let Some((d, frames)) = dbg.and_then(|d| {
        // Code without debug information (a runtime function such as
        // `__cxa_pure_virtual`): the innermost call into it that has a location.
        crash
            .calls
            .iter()
            .rev()
            .map(|c| d.frames(c.call_pc))
            .find(|f| !f.is_empty())
            .map(|f| (d, f))
    }) {
        let f0 = &frames[0];
        let callee = sym.trim_start().trim_start_matches('<');
        let callee = callee.split('+').next().unwrap_or(callee);
        let _ = writeln!(
            s,
            "  at:   {} in {}, calling {callee} (no debug information)",
            f0.location(),
            fname(f0)
        );
        if let Some(file) = &f0.file {
            if let Some(line) = d.source_line(file, f0.line) {
                let _ = writeln!(s, "  {:>5} | {}", f0.line, line.trim_end());
            }
        }
    }
    let _ = writeln!(s, "backtrace:");
    let mut n = 0;
    let mut emit = |s: &mut String, pc: u32, frames: Option<&[SourceFrame]>| match frames
        .filter(|f| !f.is_empty())
    {
        Some(frames) => {
            for f in frames {
                let inl = if f.inlined { " (inlined)" } else { "" };
                let _ = writeln!(
                    s,
                    "  #{n:<2} {pc:#010x} {}{inl} at {}",
                    fname(f),
                    f.location()
                );
                n += 1;
            }
        }
        None => {
            let name = exe
                .and_then(|e| e.symbol_at(pc))
                .map(|(s, off)| format!("{}+{off:#x}", demangle(&s.name)))
                .unwrap_or_else(|| "??".into());
            let _ = writeln!(s, "  #{n:<2} {pc:#010x} {name}");
            n += 1;
        }
    };
    emit(&mut s, crash.pc, frames.as_deref());
    for c in crash.calls.iter().rev() {
        let f = dbg.map(|d| d.frames(c.call_pc));
        emit(&mut s, c.call_pc, f.as_deref());
    }
    s
}

fn fname(f: &SourceFrame) -> String {
    f.function
        .as_deref()
        .map(demangle)
        .unwrap_or_else(|| "??".into())
}

/// Demangles a Rust symbol name (other names are returned unchanged).
pub fn demangle(name: &str) -> String {
    format!("{:#}", rustc_demangle::demangle(name))
}

impl SourceFrame {
    /// Where this (inlined) frame's code was called from in `caller`: the caller frame's
    /// own location is the call site in addr2line's model.
    fn call_site_hint(&self, caller: &SourceFrame) -> String {
        caller.location()
    }
}

/// Formats the report of a deadlock: every live thread of `m`, grouped by TM and what it
/// waits for (barrier, `trax.strsched`, semaphore), with the source line it waits at.
pub fn deadlock_report(
    m: &crate::machine::Machine,
    cycle: Option<u64>,
    exe: Option<&Executable>,
    dbg: Option<&DebugInfo>,
) -> String {
    use crate::decode::Inst;
    use crate::thread::RunState;
    use trax_runtime::isa::TraxOp;
    let sh = &m.shared;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "error: deadlock{}: {} live thread(s) all wait for one another, and none can run:",
        cycle.map_or(String::new(), |c| format!(" at cycle {c}")),
        sh.live_threads
    );
    // The source frames at `pc` (inlined ones first), then the call sites of the shadow
    // call stack, at most four in all.
    let place = |t: &crate::thread::Thread, pc: u32| -> String {
        let mut parts = Vec::new();
        for p in std::iter::once(pc).chain(t.calls.iter().rev().map(|c| c.call_pc)) {
            let frames = dbg.map(|d| d.frames(p));
            match frames.as_deref().filter(|f| !f.is_empty()) {
                Some(fs) => parts.extend(
                    fs.iter()
                        .map(|f| format!("{} ({})", fname(f), f.location())),
                ),
                None => parts.push(match exe.and_then(|e| e.symbol_at(p)) {
                    Some((sym, off)) => format!("{}+{off:#x}", demangle(&sym.name)),
                    None => format!("{p:#010x}"),
                }),
            }
            if parts.len() >= 4 {
                break;
            }
        }
        parts.truncate(4);
        format!("in {}", parts.join(" <- "))
    };
    // (TM, what, where) per live thread, in thread order.
    let mut rows: Vec<(u32, u32, String)> = Vec::new();
    for t in &m.threads {
        let what = match t.state {
            RunState::Halted => continue,
            RunState::Barrier { reg, .. } => format!(
                "trax.barrier G[{reg}] ({} of {} live threads arrived) {}",
                sh.barrier_waiting[reg as usize],
                sh.live_threads,
                place(t, t.wait_pc)
            ),
            RunState::StreamWait { .. } => {
                let ts = &sh.sched.tms[t.tm as usize];
                let why = if ts.idle {
                    "its TM drained and every ray buffer is empty: waiting for a ray".to_string()
                } else {
                    format!(
                        "waiting for {} more live thread(s) of its TM",
                        ts.live.saturating_sub(ts.waiting)
                    )
                };
                format!("trax.strsched ({why}) {}", place(t, t.wait_pc))
            }
            RunState::Running => match sh.program.get(t.pc) {
                Some(Inst::Trax {
                    op: TraxOp::SemAcquire,
                    rs,
                    ..
                }) => {
                    let reg = t.regs.gpr[(*rs & 31) as usize];
                    format!("trax.semacq G[{reg}] (0) {}", place(t, t.pc))
                }
                _ => format!("runnable {}", place(t, t.pc)),
            },
        };
        rows.push((t.gid, t.tm, what));
    }
    let mut i = 0;
    while i < rows.len() {
        let (g0, tm, what) = &rows[i];
        let mut j = i + 1;
        while j < rows.len()
            && rows[j].1 == *tm
            && rows[j].2 == *what
            && rows[j].0 == g0 + (j - i) as u32
        {
            j += 1;
        }
        let who = if j - i == 1 {
            format!("thread {g0}")
        } else {
            format!("threads {g0}-{}", rows[j - 1].0)
        };
        let _ = writeln!(s, "  {who} (TM {tm}): {what}");
        i = j;
    }
    s
}
