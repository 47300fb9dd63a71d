//! The progress line of long runs: a spinner on stderr with what has been simulated so
//! far. Hidden when stderr is not a terminal (tests, pipes, CI logs stay clean).

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use trax_emulator::Progress;

/// A live progress line.
pub struct ProgressLine {
    bar: ProgressBar,
    start: Instant,
    threads: u32,
}

impl ProgressLine {
    /// Starts the line for a chip of `threads` hardware threads.
    pub fn start(threads: u32) -> ProgressLine {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.enable_steady_tick(Duration::from_millis(200));
        ProgressLine {
            bar,
            start: Instant::now(),
            threads,
        }
    }

    /// Shows a run's progress (the cycle in timing mode).
    pub fn show(&self, p: &Progress) {
        let secs = self.start.elapsed().as_secs_f64().max(1e-9);
        let cycle = p.cycles.map_or(String::new(), |c| format!("cycle {c} | "));
        self.bar.set_message(format!(
            "{cycle}{:.1} M instr ({:.1} M/s) | {} rays | {}/{} live",
            p.instructions as f64 / 1e6,
            p.instructions as f64 / secs / 1e6,
            p.rays,
            p.live_threads,
            self.threads
        ));
    }

    /// Prints `text` on stderr above the line.
    pub fn print(&self, text: &str) {
        self.bar.suspend(|| eprint!("{text}"));
    }

    /// Removes the line.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
