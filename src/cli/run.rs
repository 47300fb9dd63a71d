//! `trax run KERNEL.rs|KERNEL.elf`: builds the kernel when given source, lays out memory
//! with the scene, runs it on the simulated chip (cycle-level by default, `--functional` for
//! execution only), reports statistics and writes the framebuffer as PNG.
//!
//! The work is in [`super::prepare`] (build + memory image), [`trax_emulator::timing::run`]
//! and [`trax_emulator::session::run`] (execution); this module parses arguments and reports.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use trax_emulator::machine::MachineConfig;
use trax_emulator::memory::Segment;
use trax_emulator::session::{run as run_session, RunRequest};
use trax_emulator::timing::{self, ChipConfig, TimingRequest};
use trax_emulator::Outcome;
use trax_runtime::host::framebuffer_rgb8;

use super::common::RenderArgs;
use super::native::write_png;
use super::prepare::prepare;

/// Arguments of `trax run`.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// The kernel: TRaX-Rust source (`.rs`, built first) or a linked executable (ELF).
    pub kernel: PathBuf,
    /// Optimisation level when building from source (`-O0` .. `-O3`).
    #[arg(short = 'O', default_value_t = 2, value_parser = clap::value_parser!(u8).range(0..=3))]
    pub opt_level: u8,
    /// Scene and image parameters.
    #[command(flatten)]
    pub render: RenderArgs,
    /// Chip configuration: a preset (`tiny`, `baseline`, `strata`) or a TOML file.
    #[arg(long, default_value = "tiny")]
    pub config: String,
    /// Thread multiprocessors (overrides the config).
    #[arg(long)]
    pub tms: Option<u32>,
    /// Threads per TM (overrides the config).
    #[arg(long)]
    pub threads: Option<u32>,
    /// Number of L2 caches; TMs are split evenly among them (overrides the config).
    #[arg(long)]
    pub l2s: Option<u32>,
    /// Functional mode: execute without the timing model (fast; no cycle statistics).
    #[arg(long)]
    pub functional: bool,
    /// Host threads for the timing simulation (results are identical for any value).
    #[arg(long, default_value_t = 1)]
    pub host_threads: usize,
    /// Write the statistics as JSON to this file.
    #[arg(long)]
    pub stats_json: Option<PathBuf>,
    /// Functional mode: instructions each thread runs per turn of the interleaving.
    #[arg(long, default_value_t = 1000)]
    pub quantum: u32,
    /// Stop after this many instructions in total (functional) or cycles (timing).
    #[arg(long)]
    pub max_instructions: Option<u64>,
    /// Write the framebuffer as PNG (clamped, top row first).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
}

/// Runs `trax run`.
pub fn run(a: RunArgs) -> ExitCode {
    match execute(&a) {
        Ok(code) => code,
        Err(msg) => {
            eprint!("{}", with_newline(format!("error: {msg}")));
            ExitCode::FAILURE
        }
    }
}

/// The chip: the named config with the command-line overrides applied.
fn chip_config(a: &RunArgs) -> Result<ChipConfig, String> {
    let mut chip = ChipConfig::load(&a.config).map_err(|e| e.to_string())?;
    for (flag, v) in [("tms", a.tms), ("threads", a.threads), ("l2s", a.l2s)] {
        if v == Some(0) {
            return Err(format!("--{flag} must be at least 1"));
        }
    }
    if let Some(t) = a.tms {
        chip.tms = t;
    }
    if let Some(t) = a.threads {
        chip.threads_per_tm = t;
    }
    if let Some(l2s) = a.l2s {
        if l2s > chip.tms {
            return Err(format!("--l2s {l2s} is more than the {} TMs", chip.tms));
        }
        chip.tms_per_l2 = chip.tms.div_ceil(l2s);
    }
    chip.validate().map_err(|e| e.to_string())?;
    Ok(chip)
}

fn execute(a: &RunArgs) -> Result<ExitCode, String> {
    if a.quantum == 0 {
        return Err("--quantum must be at least 1".into());
    }
    if a.host_threads == 0 {
        return Err("--host-threads must be at least 1".into());
    }
    for out in a.output.iter().chain(&a.stats_json) {
        if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
            if !dir.is_dir() {
                return Err(format!(
                    "{}: the output directory does not exist",
                    out.display()
                ));
            }
        }
    }
    let chip = chip_config(a)?;
    let prepared = match prepare(&a.kernel, a.opt_level, &a.render) {
        Ok(p) => p,
        Err(e) => {
            eprint!("{}", with_newline(format!("error: {e}")));
            return Ok(ExitCode::from(e.exit_code()));
        }
    };
    let fb = prepared.image.header.framebuffer;
    let segments: Vec<Segment> = prepared
        .image
        .segments
        .iter()
        .map(|g| Segment {
            addr: g.addr,
            data: g.data.clone(),
            mem_size: g.size,
            writable: true,
        })
        .collect();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let start = std::time::Instant::now();
    let threads = chip.tms * chip.threads_per_tm;
    let (outcome, report, machine) = if a.functional {
        let config = MachineConfig {
            tms: chip.tms,
            threads_per_tm: chip.threads_per_tm,
            stack_size: prepared.image.stack.size,
            quantum: a.quantum,
            max_instructions: a.max_instructions,
        };
        let req = RunRequest {
            elf_path: &prepared.name,
            elf: &prepared.elf,
            segments: Some(segments),
            config,
        };
        let r = run_session(req, &mut out).map_err(|e| format!("{}: {e}", prepared.name))?;
        let _ = out.flush();
        let secs = start.elapsed().as_secs_f64();
        let n = r.summary.instructions;
        eprintln!(
            "{n} instructions in {secs:.3} s ({:.1} M instr/s), {threads} thread(s), functional",
            n as f64 / secs.max(1e-9) / 1e6,
        );
        if r.summary.stats[0] > 0 {
            eprintln!("rays: {}", r.summary.stats[0]);
        }
        if let Some(path) = &a.stats_json {
            let json = serde_json::json!({
                "mode": "functional",
                "threads": threads,
                "instructions": n,
                "rays": r.summary.stats[0],
            });
            write_json(path, &json)?;
        }
        (r.summary.outcome, r.report, r.machine)
    } else {
        let req = TimingRequest {
            elf_path: &prepared.name,
            elf: &prepared.elf,
            segments: Some(segments),
            host_threads: a.host_threads,
            max_cycles: a.max_instructions,
        };
        let r = timing::run(req, &chip, &mut out).map_err(|e| format!("{}: {e}", prepared.name))?;
        let _ = out.flush();
        let secs = start.elapsed().as_secs_f64();
        eprint!("{}", with_newline(r.stats.summary()));
        eprintln!("simulated in {secs:.3} s");
        if let Some(path) = &a.stats_json {
            let json = serde_json::to_value(&r.stats).map_err(|e| e.to_string())?;
            write_json(path, &json)?;
        }
        (r.outcome, r.report, r.machine)
    };
    let finished = matches!(outcome, Outcome::Finished);
    if let (true, Some(path)) = (finished, &a.output) {
        let (w, h) = (a.render.width, a.render.height);
        let bytes = machine
            .shared
            .mem
            .read_bytes(&[], fb.addr, fb.count * 12)
            .unwrap_or_default();
        write_png(path, w, h, &framebuffer_rgb8(&bytes, w, h)).map_err(|e| e.to_string())?;
        eprintln!("wrote {}", path.display());
    }
    match (&outcome, &report) {
        (Outcome::Finished, _) => Ok(ExitCode::SUCCESS),
        (_, Some(report)) => {
            eprint!("{}", with_newline(report.clone()));
            Ok(ExitCode::FAILURE)
        }
        (outcome, None) => Err(format!("{}: {outcome:?}", prepared.name)),
    }
}

fn write_json(path: &std::path::Path, value: &serde_json::Value) -> Result<(), String> {
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    std::fs::write(path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))
}

fn with_newline(mut s: String) -> String {
    if !s.ends_with('\n') {
        s.push('\n');
    }
    s
}
