//! `trax run KERNEL.rs|KERNEL.elf`: builds the kernel when given source, lays out memory
//! with the scene, runs it on the simulated chip (cycle-level by default, `--functional` for
//! execution only), reports statistics and writes the framebuffer as PNG.
//!
//! The work is in [`super::prepare`] (build + memory image), [`trax_emulator::timing::run`]
//! and [`trax_emulator::session::run`] (execution); this module parses arguments and reports.
//! `--profile` charges every instruction (functional) or thread-cycle (timing) to its call
//! stack ([`trax_emulator::profile`]); `--gdb ADDR` serves the run to gdb-multiarch
//! ([`trax_emulator::gdb`]). [`execute`] is shared with `trax annotate`.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use trax_emulator::debuginfo::DebugInfo;
use trax_emulator::elf::Executable;
use trax_emulator::machine::{Machine, MachineConfig};
use trax_emulator::memory::Segment;
use trax_emulator::profile::{profile_run, Profile};
use trax_emulator::session::{self, load_debug, RunRequest};
use trax_emulator::timing::{self, ChipConfig, TimingRequest, DEFAULT_CHIP};
use trax_emulator::{crash, gdb, Outcome};
use trax_runtime::abi::PIXEL_BYTES;
use trax_runtime::host::framebuffer_rgb8;

use super::common::{self, RenderArgs};
use super::native::write_png;
use super::prepare::prepare;
use super::progress::ProgressLine;

/// Arguments of `trax run`.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// Kernel, scene, chip and run parameters.
    #[command(flatten)]
    pub exec: ExecArgs,
    /// Profile the run: instructions (functional) or thread-cycles with the stall
    /// breakdown (timing), charged to full source call stacks.
    #[arg(long)]
    pub profile: bool,
    /// Profile output format (`tree` is printed after the program's output).
    #[arg(long, value_enum, default_value_t = ProfileFormat::Tree, requires = "profile")]
    pub profile_format: ProfileFormat,
    /// Write the profile here (default for `folded`: profile.folded, for `speedscope`:
    /// profile.speedscope.json; `tree` goes to stdout unless this is given).
    #[arg(long, requires = "profile")]
    pub profile_out: Option<PathBuf>,
    /// Serve the run to GDB (gdb-multiarch `target remote ADDR`) on this address, e.g.
    /// 127.0.0.1:1234 (functional mode).
    #[arg(long, value_name = "ADDR", conflicts_with = "profile")]
    pub gdb: Option<String>,
    /// Allow a non-loopback `--gdb` address (anyone who can connect controls the run).
    #[arg(long, requires = "gdb")]
    pub gdb_allow_remote: bool,
}

/// Profile output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProfileFormat {
    /// Indented call tree with inclusive and self percentages.
    Tree,
    /// Folded stacks (`a;b;c N` lines), flame-graph input.
    Folded,
    /// speedscope JSON (https://www.speedscope.app).
    Speedscope,
}

/// What to do besides running: profile, or serve to GDB.
#[derive(Clone, Debug, Default)]
pub struct Extras {
    /// Collect a profile.
    pub profile: bool,
    /// GDB server address and whether non-loopback addresses are allowed.
    pub gdb: Option<(String, bool)>,
}

/// A finished run as [`execute`] reports it.
pub struct Executed {
    /// The process exit code.
    pub code: ExitCode,
    /// The resolved profile (when asked for and the run got going) and the DWARF.
    pub profile: Option<(Profile, Option<DebugInfo>)>,
}

/// Kernel, scene, chip and run parameters shared by `trax run` and `trax annotate`.
#[derive(Args, Debug)]
pub struct ExecArgs {
    /// The kernel: TRaX-Rust source (`.rs`, built first) or a linked executable (ELF).
    pub kernel: PathBuf,
    /// Optimisation level when building from source (`-O0` .. `-O3`).
    #[arg(short = 'O', default_value_t = 2, value_parser = clap::value_parser!(u8).range(0..=3))]
    pub opt_level: u8,
    /// Scene and image parameters.
    #[command(flatten)]
    pub render: RenderArgs,
    /// Chip configuration: a preset (`tiny`, `baseline`, `strata`) or a TOML file.
    #[arg(long, default_value = DEFAULT_CHIP)]
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
    /// Set any chip config field by its dotted path, as a line of the config file would
    /// (`--set memory.l2.capacity_bytes=262144`, `--set memory.dram.preset=hbm2`); VALUE is
    /// TOML (a bare word is a string). Repeatable; applied before `--tms/--threads/--l2s`.
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = parse_set)]
    pub set: Vec<(String, toml::Value)>,
    /// Functional mode: execute without the timing model (fast; no cycle statistics).
    #[arg(long)]
    pub functional: bool,
    /// Host threads for the timing simulation; default: the host's cores (at most one per
    /// TM). Results are identical for any value.
    #[arg(long)]
    pub host_threads: Option<usize>,
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
    /// Also write the raw framebuffer: `width*height` pixels of 3 little-endian f32 (as
    /// `trax native --raw-framebuffer`).
    #[arg(long)]
    pub raw_framebuffer: Option<PathBuf>,
}

/// Runs `trax run`.
pub fn run(a: RunArgs) -> ExitCode {
    let extras = Extras {
        profile: a.profile,
        gdb: a.gdb.clone().map(|g| (g, a.gdb_allow_remote)),
    };
    if a.gdb.is_some() && !a.exec.functional {
        return fail("--gdb needs --functional (the debugger drives the functional core)".into());
    }
    let done = match execute(&a.exec, &extras) {
        Ok(d) => d,
        Err(msg) => return fail(msg),
    };
    if let Some((profile, _)) = &done.profile {
        if let Err(msg) = write_profile(&a, profile) {
            return fail(msg);
        }
    }
    done.code
}

/// Prints `error: msg` and gives the failure exit code.
pub fn fail(msg: String) -> ExitCode {
    eprint!("{}", with_newline(format!("error: {msg}")));
    ExitCode::FAILURE
}

/// Prints or writes the profile in the requested format.
fn write_profile(a: &RunArgs, p: &Profile) -> Result<(), String> {
    let (text, default) = match a.profile_format {
        ProfileFormat::Tree => (p.render_tree(TREE_MIN_PERCENT), None),
        ProfileFormat::Folded => (p.folded(), Some("profile.folded")),
        ProfileFormat::Speedscope => {
            let name = a.exec.kernel.display().to_string();
            (p.speedscope(&name), Some("profile.speedscope.json"))
        }
    };
    match a
        .profile_out
        .as_deref()
        .or(default.map(std::path::Path::new))
    {
        Some(path) => {
            std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!("wrote profile to {}", path.display());
        }
        None => {
            let stdout = std::io::stdout();
            let mut out = stdout.lock();
            let _ = out.write_all(text.as_bytes());
            let _ = out.flush();
        }
    }
    Ok(())
}

/// Call-tree nodes below this inclusive percentage are left out of the printed tree.
const TREE_MIN_PERCENT: f64 = 0.1;

/// Parses `--set PATH=VALUE`: VALUE as a TOML value, or else as a string.
pub fn parse_set(s: &str) -> Result<(String, toml::Value), String> {
    let (path, raw) = s
        .split_once('=')
        .ok_or_else(|| format!("{s:?}: expected PATH=VALUE"))?;
    let path = path.trim();
    if path.is_empty() {
        return Err(format!("{s:?}: no field path before `=`"));
    }
    let raw = raw.trim();
    let value = toml::from_str::<toml::Table>(&format!("v = {raw}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(raw.to_string()));
    Ok((path.to_string(), value))
}

/// The chip: the named config with the command-line overrides applied.
fn chip_config(a: &ExecArgs) -> Result<ChipConfig, String> {
    common::chip_config(&a.config, &a.set, a.tms, a.threads, a.l2s)
}

/// Prepares and runs the kernel, reports statistics, writes the PNG; with `extras`,
/// profiles the run or serves it to GDB.
pub fn execute(a: &ExecArgs, extras: &Extras) -> Result<Executed, String> {
    if a.quantum == 0 {
        return Err("--quantum must be at least 1".into());
    }
    if a.host_threads == Some(0) {
        return Err("--host-threads must be at least 1".into());
    }
    for out in a
        .output
        .iter()
        .chain(&a.stats_json)
        .chain(&a.raw_framebuffer)
    {
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
            eprint!("{}", e.render());
            return Ok(Executed {
                code: ExitCode::from(e.exit_code()),
                profile: None,
            });
        }
    };
    let fb = prepared.image.header.framebuffer;
    let segments: Vec<Segment> = prepared.image.memory.segments.clone();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let start = std::time::Instant::now();
    let threads = chip.tms * chip.threads_per_tm;
    let mut profile = None;
    let (outcome, report, machine) = if a.functional {
        let config = MachineConfig {
            tms: chip.tms,
            threads_per_tm: chip.threads_per_tm,
            stack_size: prepared.image.stack.size,
            quantum: a.quantum,
            max_instructions: a.max_instructions,
        };
        let r = if extras.profile || extras.gdb.is_some() {
            run_functional_extra(
                &prepared.name,
                &prepared.elf,
                segments,
                config,
                extras,
                &mut out,
            )?
        } else {
            let req = RunRequest {
                elf_path: &prepared.name,
                elf: &prepared.elf,
                segments: Some(segments),
                config,
            };
            let line = ProgressLine::start(threads);
            let mut show = |p: &session::Progress| line.functional(p);
            let r = session::run_with(req, &mut out, Some(&mut show));
            line.finish();
            let r = r.map_err(|e| format!("{}: {e}", prepared.name))?;
            FunctionalRun {
                outcome: r.summary.outcome,
                instructions: r.summary.instructions,
                rays: r.summary.stats.first().copied().unwrap_or(0),
                report: r.report,
                machine: r.machine,
                profile: None,
            }
        };
        let _ = out.flush();
        profile = r.profile;
        let secs = start.elapsed().as_secs_f64();
        let n = r.instructions;
        eprintln!(
            "{n} instructions in {secs:.3} s ({:.1} M instr/s), {threads} thread(s), functional",
            n as f64 / secs.max(1e-9) / 1e6,
        );
        if r.rays > 0 {
            eprintln!("rays: {}", r.rays);
        }
        eprint!("{}", common::scene_report(&prepared.image));
        if let Some(path) = &a.stats_json {
            let json = serde_json::json!({
                "mode": "functional",
                "threads": threads,
                "instructions": n,
                "rays": r.rays,
                "scene": common::scene_json(&prepared.image),
            });
            write_json(path, &json)?;
        }
        (r.outcome, r.report, r.machine)
    } else {
        // One host thread per TM at most; profiling runs on one (same results).
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let host_threads = if extras.profile {
            1
        } else {
            a.host_threads
                .unwrap_or(cores)
                .min(chip.tms as usize)
                .max(1)
        };
        if host_threads > cores {
            eprintln!(
                "warning: {host_threads} host threads on {cores} available core(s): host threads work in lock-step rounds, so more of them than cores makes the run slower (results are the same)"
            );
        }
        let req = TimingRequest {
            elf_path: &prepared.name,
            elf: &prepared.elf,
            segments: Some(segments),
            host_threads,
            max_cycles: a.max_instructions,
        };
        let line = ProgressLine::start(chip.tms * chip.threads_per_tm);
        let mut show = |p: &timing::Progress| line.timing(p);
        let res = timing::run_with(req, &chip, &mut out, extras.profile, Some(&mut show));
        line.finish();
        let (r, prof) = res.map_err(|e| format!("{}: {e}", prepared.name))?;
        let _ = out.flush();
        if let Some(prof) = prof {
            let dbg = load_debug(&prepared.name, &prepared.elf).ok();
            profile = Some((Profile::build(&prof, dbg.as_ref(), Some(&r.exe)), dbg));
        }
        let secs = start.elapsed().as_secs_f64();
        eprint!("{}", with_newline(r.stats.summary()));
        eprint!("{}", common::scene_report(&prepared.image));
        eprintln!("simulated in {secs:.3} s on {host_threads} host thread(s)");
        if let Some(path) = &a.stats_json {
            let mut json = serde_json::to_value(&r.stats).map_err(|e| e.to_string())?;
            if let Some(obj) = json.as_object_mut() {
                obj.insert("scene".into(), common::scene_json(&prepared.image));
            }
            write_json(path, &json)?;
        }
        (r.outcome, r.report, r.machine)
    };
    let finished = matches!(outcome, Outcome::Finished);
    if finished && (a.output.is_some() || a.raw_framebuffer.is_some()) {
        let bytes = machine
            .shared
            .mem
            .read_bytes(&[], fb.addr, fb.count * PIXEL_BYTES)
            .unwrap_or_default();
        if let Some(path) = &a.output {
            let (w, h) = (a.render.width, a.render.height);
            write_png(path, w, h, &framebuffer_rgb8(&bytes, w, h)).map_err(|e| e.to_string())?;
            eprintln!("wrote {}", path.display());
        }
        if let Some(path) = &a.raw_framebuffer {
            std::fs::write(path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    let code = match (&outcome, &report) {
        (Outcome::Finished, _) => ExitCode::SUCCESS,
        (_, Some(report)) => {
            eprint!("{}", with_newline(report.clone()));
            ExitCode::FAILURE
        }
        (outcome, None) => return Err(format!("{}: {outcome:?}", prepared.name)),
    };
    Ok(Executed { code, profile })
}

/// A functional run's results, however it was driven.
struct FunctionalRun {
    outcome: Outcome,
    instructions: u64,
    rays: u64,
    report: Option<String>,
    machine: Machine,
    profile: Option<(Profile, Option<DebugInfo>)>,
}

/// A functional run with profiling or under GDB (the plain one is
/// [`trax_emulator::session::run`]).
fn run_functional_extra(
    name: &str,
    elf: &[u8],
    segments: Vec<Segment>,
    config: MachineConfig,
    extras: &Extras,
    out: &mut dyn Write,
) -> Result<FunctionalRun, String> {
    let exe = Executable::parse(name, elf).map_err(|e| format!("{name}: {e}"))?;
    let mut machine = Machine::new(&segments, exe.text_start, exe.text_end, exe.entry, config)
        .map_err(|e| format!("{name}: {e}"))?;
    let mut profile = None;
    let (outcome, instructions) = if let Some((addr, allow_remote)) = &extras.gdb {
        let listener = gdb::bind(addr, *allow_remote).map_err(|e| e.to_string())?;
        let local = listener.local_addr().map_err(|e| e.to_string())?;
        eprintln!("waiting for gdb on {local}");
        let outcome =
            gdb::serve_listener(&mut machine, listener, out).map_err(|e| e.to_string())?;
        match outcome {
            Some(o) => (o, retired(&machine)),
            None => {
                eprintln!("gdb detached before the program ended; running it to completion");
                let s = machine.run(out);
                (s.outcome, retired(&machine))
            }
        }
    } else {
        let (summary, prof) = profile_run(&mut machine, out);
        let dbg = load_debug(name, elf).ok();
        profile = Some((Profile::build(&prof, dbg.as_ref(), Some(&exe)), dbg));
        (summary.outcome, summary.instructions)
    };
    let report = match &outcome {
        Outcome::Finished => None,
        Outcome::Crashed(c) => {
            let dbg = load_debug(name, elf).ok();
            Some(crash::report(c, &machine.shared, Some(&exe), dbg.as_ref()))
        }
        Outcome::Deadlock { waiting } => Some(format!(
            "error: deadlock: {waiting} live thread(s) are all waiting at barriers or semaphores"
        )),
        Outcome::InstructionLimit => Some(format!(
            "error: instruction limit reached after {instructions} instructions"
        )),
    };
    Ok(FunctionalRun {
        outcome,
        instructions,
        rays: machine.shared.stats.first().copied().unwrap_or(0),
        report,
        machine,
        profile,
    })
}

/// Instructions retired by every thread so far.
fn retired(m: &Machine) -> u64 {
    m.threads.iter().map(|t| t.retired).sum()
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
