//! Exact profiler: every unit of cost charged to the full source call stack.
//!
//! Library API (the `trax run --profile` / `trax annotate` CLI wires these):
//!
//! - [`profile_run`]`(&mut machine, out, on_livelock) -> (RunSummary, Profiler)` is a drop-in for
//!   [`crate::Machine::run`] (same thread interleaving, see [`crate::sched`], same summary) that
//!   also charges every retired instruction to its thread's interned shadow call stack
//!   and pc.
//! - Timing runs: create [`Profiler::new`]`(&machine.shared.program, threads)` and call
//!   [`Profiler::charge`]`(thread_index, &thread.calls, pc, kind, amount)` for each issue
//!   or stall cycle, with a [`CostKind`] naming the stall.
//! - [`Profile::build`]`(&profiler, Some(&debuginfo), Some(&exe))` resolves pcs to source
//!   frames once (inlined frames from DWARF via [`crate::debuginfo`], real calls from the
//!   shadow stack) and gives [`Profile::render_tree`] (thesis Figure 6.1 style, inclusive
//!   and self %), [`Profile::folded`] (flame-graph input), [`Profile::speedscope`] (JSON)
//!   and [`Profile::annotate`] (per-source-line costs next to the source text).
//!
//! Cost: one hash update per executed basic block (functional mode); pcs are resolved
//! only at the end. `benches/profile.rs` measures the overhead.

pub mod collect;
pub mod report;

use std::io::Write;

pub use collect::{CostKind, ProfileExec, Profiler, KINDS};
pub use report::{Frame, Profile, TreeNode};

use crate::livelock::Detection;
use crate::machine::{Machine, RunSummary};
use crate::sched::Scheduler;

/// Runs `m` to the end like [`Machine::run`], with every retired instruction charged to
/// its call stack. Returns the run summary and the collected profile.
/// With `on_livelock`, watches for a livelock as [`Machine::run_with`] does.
pub fn profile_run(
    m: &mut Machine,
    out: &mut dyn Write,
    on_livelock: Option<&mut dyn FnMut(&Detection) -> bool>,
) -> (RunSummary, Profiler) {
    let mut prof = Profiler::new(&m.shared.program, m.threads.len());
    let mut sched = Scheduler::new(m);
    let mut e = ProfileExec {
        profiler: &mut prof,
    };
    let outcome = sched.run_to_end(m, out, &mut e, on_livelock);
    let summary = RunSummary {
        outcome,
        instructions: sched.total,
        stats: m.shared.stats.to_vec(),
        profile: m.shared.profile.to_vec(),
    };
    (summary, prof)
}
