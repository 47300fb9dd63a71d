//! `trax annotate KERNEL.rs|.c|.cpp|KERNEL.elf`: runs the kernel with profiling (same flags as
//! `trax run`) and prints per-source-line costs next to the source text: instructions in
//! functional mode, thread-cycles (issue plus stalls) in timing mode.

use std::io::Write;
use std::process::ExitCode;

use clap::Args;

use super::run::{execute, fail, ExecArgs, Extras};

/// Arguments of `trax annotate`.
#[derive(Args, Debug)]
pub struct AnnotateArgs {
    /// Kernel, scene, chip and run parameters (as for `trax run`).
    #[command(flatten)]
    pub exec: ExecArgs,
}

/// Runs `trax annotate`.
pub fn run(a: AnnotateArgs) -> ExitCode {
    let extras = Extras {
        profile: true,
        gdb: None,
    };
    let done = match execute(&a.exec, &extras) {
        Ok(d) => d,
        Err(msg) => return fail(msg),
    };
    if let Some((profile, dbg)) = &done.profile {
        let text = profile.annotate(dbg.as_ref());
        let stdout = std::io::stdout();
        let mut out = stdout.lock();
        let _ = out.write_all(text.as_bytes());
        let _ = out.flush();
    }
    done.code
}
