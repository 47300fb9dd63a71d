//! Where the threads are: every live thread's state and source call stack, threads with
//! the same state and stack (function and line of every frame, inlined frames included)
//! grouped and counted, largest group first — a `thread apply all bt` summary for a run
//! stopped by a limit. Text for the terminal and a serializable form for the stats JSON.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::crash::demangle;
use crate::debuginfo::DebugInfo;
use crate::elf::Executable;
use crate::thread::{RunState, Thread};

/// Frames of a stack shown (innermost first); deeper ones are counted, not listed.
const MAX_FRAMES: usize = 12;
/// Groups listed in the text; the rest are summed in one line.
const MAX_GROUPS: usize = 12;

/// One source frame of a group's stack.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub struct PlaceFrame {
    /// Function (demangled), or the symbol+offset / address without debug information.
    pub function: String,
    /// Source file (`null` without debug information).
    pub file: Option<String>,
    /// Line (0: unknown).
    pub line: u32,
    /// Inlined into the next frame.
    pub inlined: bool,
}

/// Threads in the same state at the same source stack.
#[derive(Clone, Debug, Serialize)]
pub struct PlaceGroup {
    /// How many threads.
    pub count: u32,
    /// Their global thread ids, as ranges (`0-3, 8`).
    pub threads: String,
    /// `running`, `barrier G[N]`, `stream wait` or `semaphore G[N]`.
    pub state: String,
    /// The stack, innermost frame first (at most 12; `more_frames` beyond).
    pub frames: Vec<PlaceFrame>,
    /// Frames of a deeper stack not listed.
    pub more_frames: u32,
}

/// Where every live thread is.
#[derive(Clone, Debug, Serialize)]
pub struct ThreadPlaces {
    /// Threads not halted.
    pub live: u32,
    /// Threads halted.
    pub halted: u32,
    /// The groups, largest first (ties by first thread).
    pub groups: Vec<PlaceGroup>,
}

/// Thread ids as ranges: `0-3, 8, 10-11`.
fn ranges(ids: &[u32]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < ids.len() {
        let mut j = i;
        while j + 1 < ids.len() && ids[j + 1] == ids[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            ids[i].to_string()
        } else {
            format!("{}-{}", ids[i], ids[j])
        });
        i = j + 1;
    }
    parts.join(", ")
}

/// The source frames of `pc` (innermost first), or its symbol without debug information.
fn frames_at(pc: u32, exe: Option<&Executable>, dbg: Option<&DebugInfo>) -> Vec<PlaceFrame> {
    let frames = dbg.map(|d| d.frames(pc));
    match frames.as_deref().filter(|f| !f.is_empty()) {
        Some(fs) => fs
            .iter()
            .map(|f| PlaceFrame {
                function: f
                    .function
                    .as_deref()
                    .map(demangle)
                    .unwrap_or_else(|| "??".into()),
                file: f.file.clone(),
                line: f.line,
                inlined: f.inlined,
            })
            .collect(),
        None => vec![PlaceFrame {
            function: match exe.and_then(|e| e.symbol_at(pc)) {
                Some((s, off)) => format!("{}+{off:#x}", demangle(&s.name)),
                None => format!("{pc:#010x}"),
            },
            file: None,
            line: 0,
            inlined: false,
        }],
    }
}

/// One live thread's place: its state and its call stack as code addresses.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ThreadAt {
    /// Global thread id.
    pub gid: u32,
    /// `running`, `barrier G[N]`, `stream wait`, or what a caller says of it.
    pub state: String,
    /// The address it is at, then the address of each call below it (innermost first).
    pub pcs: Vec<u32>,
    /// Calls not recorded (the shadow stack was full).
    pub dropped_calls: u32,
}

impl ThreadAt {
    /// Where thread `t` is (`None` once halted): a waiting thread at the instruction it
    /// waits in.
    pub fn of(t: &Thread) -> Option<ThreadAt> {
        let (state, pc) = match t.state {
            RunState::Halted => return None,
            RunState::Barrier { reg, .. } => (format!("barrier G[{reg}]"), t.wait_pc),
            RunState::StreamWait { .. } => ("stream wait".to_string(), t.wait_pc),
            RunState::Running => ("running".to_string(), t.pc),
        };
        Some(ThreadAt {
            gid: t.gid,
            state,
            pcs: std::iter::once(pc)
                .chain(t.calls.iter().rev().map(|c| c.call_pc))
                .collect(),
            dropped_calls: t.dropped_calls,
        })
    }
}

/// Where the live threads of `threads` are.
pub fn thread_places(
    threads: &[Thread],
    exe: Option<&Executable>,
    dbg: Option<&DebugInfo>,
) -> ThreadPlaces {
    let live: Vec<ThreadAt> = threads.iter().filter_map(ThreadAt::of).collect();
    let halted = (threads.len() - live.len()) as u32;
    places(&live, halted, exe, dbg)
}

/// The summary of live threads `live` (and `halted` halted ones), their addresses
/// resolved to source stacks with `exe` and `dbg`.
pub fn places(
    live: &[ThreadAt],
    halted: u32,
    exe: Option<&Executable>,
    dbg: Option<&DebugInfo>,
) -> ThreadPlaces {
    type Key = (String, Vec<PlaceFrame>, u32);
    let mut groups: BTreeMap<Key, Vec<u32>> = BTreeMap::new();
    for t in live {
        let mut stack = Vec::new();
        for &p in &t.pcs {
            stack.extend(frames_at(p, exe, dbg));
        }
        let more = stack.len().saturating_sub(MAX_FRAMES) as u32 + t.dropped_calls;
        stack.truncate(MAX_FRAMES);
        groups
            .entry((t.state.clone(), stack, more))
            .or_default()
            .push(t.gid);
    }
    let mut groups: Vec<PlaceGroup> = groups
        .into_iter()
        .map(|((state, frames, more_frames), mut ids)| {
            ids.sort_unstable();
            PlaceGroup {
                count: ids.len() as u32,
                threads: ranges(&ids),
                state,
                frames,
                more_frames,
            }
        })
        .collect();
    groups.sort_by(|a, b| {
        b.count
            .cmp(&a.count)
            .then_with(|| first_id(&a.threads).cmp(&first_id(&b.threads)))
    });
    ThreadPlaces {
        live: live.len() as u32,
        halted,
        groups,
    }
}

/// The first id of a [`ranges`] text.
fn first_id(r: &str) -> u32 {
    r.split(['-', ','])
        .next()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(u32::MAX)
}

impl ThreadPlaces {
    /// The summary as text: a header, then per group its count, state, threads and stack.
    pub fn render(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "where the threads are: {} live, {} halted",
            self.live, self.halted
        );
        for g in self.groups.iter().take(MAX_GROUPS) {
            let who = if g.count == 1 { "thread" } else { "threads" };
            let _ = writeln!(s, "  {:>5} {who} {} ({})", g.count, g.threads, g.state);
            for (i, f) in g.frames.iter().enumerate() {
                let at = match (&f.file, f.line) {
                    (Some(file), 0) => format!(" at {file}"),
                    (Some(file), l) => format!(" at {file}:{l}"),
                    (None, _) => String::new(),
                };
                let how = match i {
                    0 => "in",
                    _ if g.frames[i - 1].inlined => "inlined into",
                    _ => "called from",
                };
                let _ = writeln!(s, "        {how} {}{at}", f.function);
            }
            if g.more_frames > 0 {
                let _ = writeln!(s, "        ... {} more frame(s)", g.more_frames);
            }
        }
        if self.groups.len() > MAX_GROUPS {
            let rest = &self.groups[MAX_GROUPS..];
            let n: u32 = rest.iter().map(|g| g.count).sum();
            let _ = writeln!(
                s,
                "  {n:>5} more thread(s) in {} other place(s) (all of them in --stats-json)",
                rest.len()
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_ids_read_as_ranges() {
        assert_eq!(ranges(&[0, 1, 2, 3, 8, 10, 11]), "0-3, 8, 10-11");
        assert_eq!(ranges(&[5]), "5");
        assert_eq!(first_id("10-11, 14"), 10);
    }
}
