//! The functional scheduler, resumable and with a pluggable per-thread executor.
//!
//! [`Machine::run`] drives it with [`PlainExec`]; the profiler runs each thread's quantum
//! in basic-block chunks and the debugger pauses the chip at a breakpoint and resumes it
//! later. All share one interleaving (TM-major round robin, `quantum` instructions per
//! turn, LL link cleared on a context switch, barrier and stream-scheduler release when a
//! thread halts), so profiled and debugged runs equal ordinary ones.

use std::io::Write;

use crate::exec::Stop;
use crate::livelock::{self, Detection, Watch};
use crate::machine::{drain, Crash, Machine, Outcome};
use crate::thread::{Shared, Thread};

/// Runs one thread's turn (or part of it).
pub trait Executor {
    /// Runs thread `idx` (index in [`Machine::threads`]) for at most `budget` instructions.
    /// Returning [`Stop::Budget`] with fewer instructions retired than `budget` ends the
    /// turn early; if [`Executor::pause`] then says so, the whole chip pauses.
    fn exec(&mut self, idx: usize, t: &mut Thread, sh: &mut Shared, budget: u64) -> Stop;

    /// Whether thread `idx`'s turn passes without visiting the thread at all (no
    /// [`Thread::wake`], no [`Executor::exec`]), so a thread that sits the turn out costs
    /// the executor's own bookkeeping, not a host cache miss on its [`Thread`]. Say so only
    /// for a thread known to be running whose `exec` would retire nothing, change nothing
    /// and not pause: the run must equal the one without this hook.
    fn passes(&mut self, _idx: usize, _sh: &Shared) -> bool {
        false
    }

    /// Whether the last short [`Stop::Budget`] asks the chip to pause (a breakpoint).
    fn pause(&self) -> bool {
        false
    }
}

/// Plain execution (no instrumentation).
#[derive(Debug, Default)]
pub struct PlainExec;

impl Executor for PlainExec {
    fn exec(&mut self, _idx: usize, t: &mut Thread, sh: &mut Shared, budget: u64) -> Stop {
        t.run(sh, budget)
    }
}

/// Every instruction in the reference interpreter ([`Thread::step_once`], which the fast
/// engine of [`Thread::run`] stands in for): the same run as [`PlainExec`]'s, slower. For
/// checking the fast engine against it.
#[derive(Debug, Default)]
pub struct ReferenceExec;

impl Executor for ReferenceExec {
    fn exec(&mut self, _idx: usize, t: &mut Thread, sh: &mut Shared, budget: u64) -> Stop {
        for _ in 0..budget {
            let stop = t.step_once(sh);
            if stop != Stop::Budget {
                return stop;
            }
        }
        Stop::Budget
    }
}

/// Why [`Scheduler::run`] returned.
#[derive(Clone, Debug)]
pub enum Driven {
    /// The run is over.
    Done(Outcome),
    /// The executor paused the chip while running thread `thread`.
    Paused {
        /// Index of the thread that asked for the pause.
        thread: usize,
    },
    /// [`Scheduler::watch`] proved that the run never ends (the run can go on).
    Livelock(Box<Detection>),
}

/// Scheduler position, so a paused run resumes exactly where it stopped.
#[derive(Clone, Debug, Default)]
pub struct Scheduler {
    next: usize,
    left: Option<u64>,
    progressed: bool,
    /// Instructions retired by all threads so far.
    pub total: u64,
    done: Option<Outcome>,
    /// Watch for a livelock ([`crate::livelock`]), in rounds times the quantum; it stops
    /// watching once it found one.
    pub watch: Option<Watch>,
    rounds: u64,
}

impl Scheduler {
    /// A scheduler at the start of `m`'s run.
    pub fn new(m: &Machine) -> Scheduler {
        Scheduler {
            total: m.threads.iter().map(|t| t.retired).sum(),
            ..Scheduler::default()
        }
    }

    /// The final outcome, once the run is over.
    pub fn outcome(&self) -> Option<&Outcome> {
        self.done.as_ref()
    }

    /// Runs to the end, resuming after pauses; with `on_livelock`, watches for a
    /// livelock and tells it, ending the run with [`Outcome::Livelock`] if it says so.
    pub fn run_to_end(
        &mut self,
        m: &mut Machine,
        out: &mut dyn Write,
        e: &mut dyn Executor,
        mut on_livelock: Option<&mut dyn FnMut(&Detection) -> bool>,
    ) -> Outcome {
        if on_livelock.is_some() && self.watch.is_none() {
            self.watch = Some(Watch::default());
        }
        loop {
            match self.run(m, out, e) {
                Driven::Done(o) => return o,
                Driven::Livelock(d) => {
                    if on_livelock.as_mut().is_some_and(|f| f(&d)) {
                        self.done = Some(Outcome::Livelock);
                        return Outcome::Livelock;
                    }
                }
                Driven::Paused { .. } => {}
            }
        }
    }

    /// Runs until the end or until the executor pauses the chip.
    pub fn run(&mut self, m: &mut Machine, out: &mut dyn Write, e: &mut dyn Executor) -> Driven {
        if let Some(o) = &self.done {
            return Driven::Done(o.clone());
        }
        let d = self.run_inner(m, out, e);
        drain(&mut m.shared.output, out);
        if let Driven::Done(o) = &d {
            self.done = Some(o.clone());
        }
        d
    }

    fn run_inner(&mut self, m: &mut Machine, out: &mut dyn Write, e: &mut dyn Executor) -> Driven {
        let quantum = m.config.quantum.max(1) as u64;
        loop {
            if m.shared.live_threads == 0 {
                return Driven::Done(Outcome::Finished);
            }
            while self.next < m.threads.len() {
                let i = self.next;
                // A resumed turn (`left`) always runs.
                if self.left.is_none() && e.passes(i, &m.shared) {
                    self.next += 1;
                    continue;
                }
                let t = &mut m.threads[i];
                if !t.wake(&m.shared, u64::MAX) {
                    self.next += 1;
                    continue;
                }
                let mut budget = self.left.take().unwrap_or(quantum);
                if let Some(max) = m.config.max_instructions {
                    if self.total >= max {
                        return Driven::Done(Outcome::InstructionLimit);
                    }
                    budget = budget.min(max - self.total);
                }
                let before = t.retired;
                let stop = e.exec(i, t, &mut m.shared, budget);
                let ran = t.retired - before;
                self.total += ran;
                self.progressed |= ran != 0;
                if stop == Stop::Budget && ran < budget && e.pause() {
                    self.left = Some(budget - ran);
                    return Driven::Paused { thread: i };
                }
                t.ll_addr = None;
                self.next += 1;
                if let Some(o) = account(m, i, stop) {
                    return Driven::Done(o);
                }
            }
            self.next = 0;
            drain(&mut m.shared.output, out);
            if let Some(w) = &mut self.watch {
                self.rounds += 1;
                let now = self.rounds * quantum;
                if w.due(now, m.shared.progress_count()) {
                    match livelock::prove(m.threads.iter(), &m.shared) {
                        Some((threads, halted)) => {
                            let d = Detection {
                                cycle: None,
                                instructions: self.total,
                                quiet: w.quiet(now),
                                threads,
                                halted,
                            };
                            self.watch = None;
                            return Driven::Livelock(Box::new(d));
                        }
                        None => w.failed(),
                    }
                }
            }
            if !std::mem::take(&mut self.progressed) && m.shared.live_threads > 0 {
                let releasable = m.threads.iter().any(|t| t.releasable(&m.shared));
                if !releasable {
                    return Driven::Done(Outcome::Deadlock {
                        waiting: m.shared.live_threads,
                    });
                }
            }
        }
    }

    /// Runs up to `n` instructions of thread `idx` outside its turn (debugger single
    /// step). Returns the outcome if this ended the run (a fault or the last halt).
    pub fn step_thread(
        &mut self,
        m: &mut Machine,
        out: &mut dyn Write,
        idx: usize,
        n: u64,
    ) -> Option<Outcome> {
        if self.done.is_some() {
            return self.done.clone();
        }
        let t = &mut m.threads[idx];
        if !t.wake(&m.shared, u64::MAX) {
            return None;
        }
        let before = t.retired;
        let stop = t.run(&mut m.shared, n);
        self.total += t.retired - before;
        let o = account(m, idx, stop);
        drain(&mut m.shared.output, out);
        let o = o.or_else(|| (m.shared.live_threads == 0).then_some(Outcome::Finished));
        if let Some(o) = &o {
            self.done = Some(o.clone());
        }
        o
    }
}

/// Applies a thread's stop to the chip; returns the outcome if it ends the run.
fn account(m: &mut Machine, i: usize, stop: Stop) -> Option<Outcome> {
    match stop {
        // `Defer` does not happen with exclusive access.
        Stop::Budget | Stop::Blocked | Stop::Retry | Stop::Defer => None,
        Stop::Halted => {
            let tm = m.threads[i].tm;
            m.shared.thread_halted(tm);
            None
        }
        Stop::Fault(fault) => Some(Outcome::Crashed(Box::new(Crash::capture(
            &m.threads[i],
            fault,
        )))),
    }
}
