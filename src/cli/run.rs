//! `trax run KERNEL.rs|.c|.cpp [MORE...]|KERNEL.elf`: builds the kernel when given source
//! (several files are linked together), lays out memory with the scene, runs it on the
//! simulated chip (cycle-level by default, `--functional` for execution only), reports
//! statistics and writes the framebuffer as PNG.
//!
//! The work is in [`trax::pipeline`] (build + memory image) and [`trax_emulator::run()`]
//! (execution: functional or timing, with `--profile` every instruction or thread-cycle
//! charged to its call stack, with `--gdb ADDR` served to gdb-multiarch); this module
//! parses arguments and reports. [`execute`] is shared with `trax annotate`.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use trax::pipeline::{self, prepare, scene_report};
use trax::stats::StatsDocument;
use trax_emulator::profile::Profile;
use trax_emulator::timing::ChipConfig;
use trax_emulator::{gdb, DebugInfo, Limits, Mode, OnLivelock, DEFAULT_QUANTUM};

use super::common::{PngArgs, RenderArgs, SampleArgs, ShapeArgs};
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
    /// profile.speedscope.json, for `flamegraph`: profile.svg; `tree` goes to stdout
    /// unless this is given).
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
    /// Interactive SVG flame graph (click to zoom, search; open in a web browser).
    Flamegraph,
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
    /// The kernel, scene and chip.
    #[command(flatten)]
    pub program: ProgramArgs,
    /// Functional mode: execute without the timing model (fast; no cycle statistics).
    #[arg(long)]
    pub functional: bool,
    /// Write the statistics as JSON to this file (one shape for all modes, `schema: 1`;
    /// fields in docs/STATS.md).
    #[arg(long)]
    pub stats_json: Option<PathBuf>,
    /// Functional mode: instructions each thread runs per turn of the interleaving.
    #[arg(long, default_value_t = DEFAULT_QUANTUM)]
    pub quantum: u32,
    /// Stop once the threads have executed this many instructions in total. Timing mode
    /// counts issued instructions plus zero-cost debug ops and stops at the end of the
    /// quantum (L1 + L2 hit latency cycles) in which the count reaches N.
    #[arg(long, value_name = "N")]
    pub max_instructions: Option<u64>,
    /// Timing mode: stop at this core cycle.
    #[arg(long, value_name = "N", conflicts_with = "functional")]
    pub max_cycles: Option<u64>,
    /// Stop a run proved never to finish (a livelock: every running thread repeats a loop
    /// that changes nothing outside it, every other one waits; looked for after 2^18
    /// cycles, or instructions per thread, without a store to global memory, a
    /// global-register, barrier or stream operation, a print, counter or halt). Without
    /// it the run warns, says where the threads are, and goes on.
    #[arg(long)]
    pub stop_on_livelock: bool,
    /// Timing mode: record statistics for every N simulated cycles (issue rate, stalls,
    /// L1/L2/DRAM traffic, rays in flight, energy) as `timing.intervals` of the
    /// `--stats-json` document. N must be a multiple of the quantum (L1 + L2 hit latency).
    #[arg(long, value_name = "N")]
    pub stats_interval: Option<u64>,
    /// Sampled timing simulation: N detailed windows at seeded random points of N equal
    /// strata of the frame's pixels, the frame's first and last pixels in full, the rest
    /// fast-forwarded functionally with cache and DRAM-row warming (every pixel is
    /// rendered). Reports cycles, frames/s, MRPS, issue rate, hit rates, DRAM traffic and
    /// energy as estimate ± 95% confidence interval. At least 10.
    #[arg(long, value_name = "N", conflicts_with = "functional")]
    pub sample: Option<u32>,
    /// How `--sample` samples.
    #[command(flatten)]
    pub sampling: SampleArgs,
    /// The PNG and its exposure.
    #[command(flatten)]
    pub png: PngArgs,
    /// Also write the raw framebuffer: `width*height` pixels of 3 little-endian f32 (as
    /// `trax native --raw-framebuffer`).
    #[arg(long)]
    pub raw_framebuffer: Option<PathBuf>,
}

/// The program to run and the chip to run it on: the flags of `trax run` that `trax
/// ladder` shares.
#[derive(Args, Debug, Clone)]
pub struct ProgramArgs {
    /// The kernel: TRaX-Rust (`.rs`), C (`.c`) or C++ (`.cpp`, `.cc`) source, built
    /// first, or a linked executable (ELF).
    pub kernel: PathBuf,
    /// Further sources (`.rs`, `.c`, `.cpp`, `.cc`) and objects (`.o`) linked with the kernel.
    #[arg(value_name = "MORE")]
    pub more: Vec<PathBuf>,
    /// Optimisation level when building from source (`-O0` .. `-O3`).
    #[arg(short = 'O', default_value_t = pipeline::DEFAULT_OPT_LEVEL, value_parser = clap::value_parser!(u8).range(0..=3))]
    pub opt_level: u8,
    /// Scene and image parameters.
    #[command(flatten)]
    pub render: RenderArgs,
    /// Chip and thread shape.
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// Number of L2 caches; TMs are split evenly among them (overrides the config).
    #[arg(long)]
    pub l2s: Option<u32>,
    /// Host threads for the timing simulation; default: the host's cores (at most one per
    /// TM). Results are identical for any value.
    #[arg(long)]
    pub host_threads: Option<usize>,
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
            let name = a.exec.program.kernel.display().to_string();
            (p.speedscope(&name), Some("profile.speedscope.json"))
        }
        ProfileFormat::Flamegraph => {
            let title = format!("{} ({})", a.exec.program.kernel.display(), p.unit());
            let svg = flamegraph_svg(&p.folded(), p.unit(), &title)?;
            (svg, Some("profile.svg"))
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

/// Renders folded stacks ([`Profile::folded`]) as an interactive SVG flame graph (inferno):
/// one box per distinct call path, as wide as the path's inclusive cost; every path is
/// kept however narrow, and each box's tooltip gives its exact count in `unit`.
///
/// The folded stacks are ordered frame by frame (not as strings, where `a;f::g` would sort
/// between `a;f` and `a;f;h` and split `f` in two), so each call path is a single box.
/// Colours come from a hash of the function name: the same profile gives the same bytes.
pub fn flamegraph_svg(folded: &str, unit: &str, title: &str) -> Result<String, String> {
    let mut lines: Vec<(Vec<&str>, &str)> = folded
        .lines()
        .filter_map(|l| {
            l.rsplit_once(' ')
                .map(|(stack, _)| (stack.split(';').collect(), l))
        })
        .collect();
    if lines.is_empty() {
        return Err("the profile is empty: nothing to draw in a flame graph".into());
    }
    lines.sort();
    // inferno insists on string order unless in "flame chart" mode, which only draws
    // the lines in the order given (reversed first, hence `.rev()`).
    let ordered = lines.iter().rev().map(|(_, line)| *line);
    let mut opt = inferno::flamegraph::Options::default();
    opt.title = title.to_string();
    opt.count_name = unit.to_string();
    opt.min_width = 0.0;
    opt.flame_chart = true;
    opt.hash = true;
    opt.deterministic = true;
    let mut svg = Vec::new();
    inferno::flamegraph::from_lines(&mut opt, ordered, &mut svg)
        .map_err(|e| format!("flame graph: {e}"))?;
    String::from_utf8(svg).map_err(|e| format!("flame graph: {e}"))
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

impl ProgramArgs {
    /// The chip: the named config with the command-line overrides applied.
    pub fn chip_config(&self) -> Result<ChipConfig, String> {
        let s = &self.shape;
        pipeline::chip_config(&s.config, &s.set, s.tms, s.threads, self.l2s)
    }

    /// The pipeline request for this program on `chip`.
    pub fn request(&self, chip: &ChipConfig) -> pipeline::Request {
        let mut request = self.render.request(&self.kernel, self.opt_level, chip);
        request.more = self.more.clone();
        request
    }

    /// Pixels of the frame (the items a sampled run's counter hands out).
    pub fn pixels(&self) -> u32 {
        self.render.width.saturating_mul(self.render.height)
    }
}

/// Prepares and runs the kernel, reports statistics, writes the PNG; with `extras`,
/// profiles the run or serves it to GDB.
pub fn execute(a: &ExecArgs, extras: &Extras) -> Result<Executed, String> {
    if a.quantum == 0 {
        return Err("--quantum must be at least 1".into());
    }
    if a.stats_interval.is_some() && a.stats_json.is_none() {
        eprintln!(
            "warning: --stats-interval without --stats-json: the intervals are written only \
             to the statistics document, so none is kept"
        );
    }
    let p = &a.program;
    if p.host_threads == Some(0) {
        return Err("--host-threads must be at least 1".into());
    }
    for out in a
        .png
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
        check_writable(out)?;
    }
    let chip = p.chip_config()?;
    trax::resources::check_chip_memory(&chip, !a.functional)?;
    let sample = match a.sample {
        Some(n) => Some(a.sampling.request(n, p.pixels(), &chip)?),
        None => {
            a.sampling.unused()?;
            None
        }
    };
    let request = p.request(&chip);
    let prepared = match prepare(&request) {
        Ok(p) => p,
        Err(e) => {
            eprint!("{}", e.render());
            return Ok(Executed {
                code: ExitCode::from(e.exit_code()),
                profile: None,
            });
        }
    };
    for w in &prepared.warnings {
        eprintln!("warning: {w}");
    }
    let mode = if a.functional {
        Mode::Functional
    } else {
        Mode::Timing
    };
    let limits = Limits {
        max_instructions: a.max_instructions,
        max_cycles: a.max_cycles,
    };
    let mut req = prepared.run_request(&chip, mode);
    req.quantum = a.quantum;
    req.limits = limits;
    req.host_threads = p.host_threads;
    req.stats_interval = a.stats_interval;
    // Intervals go to a spool file as they complete (the run keeps none).
    let mut spool = match a.stats_interval.and(a.stats_json.as_ref()) {
        Some(_) => Some(
            trax::stats::IntervalSpool::new()
                .map_err(|e| format!("statistics intervals: cannot make a spool file: {e}"))?,
        ),
        None => None,
    };
    let mut to_spool = |iv: &trax_emulator::timing::Interval| {
        if let Some(s) = spool.as_mut() {
            s.push(iv);
        }
    };
    if a.stats_interval.is_some() {
        req.interval_sink = Some(&mut to_spool);
    }
    req.sample = sample;
    req.profile = extras.profile;
    if let Some((addr, allow_remote)) = &extras.gdb {
        let listener = gdb::bind(addr, *allow_remote).map_err(|e| e.to_string())?;
        let local = listener.local_addr().map_err(|e| e.to_string())?;
        eprintln!("waiting for gdb on {local}");
        req.gdb = Some(listener);
    }
    // A functional run under the profiler or the debugger reports no progress.
    let line = (mode == Mode::Timing || !(extras.profile || extras.gdb.is_some()))
        .then(|| ProgressLine::start(chip.tms * chip.threads_per_tm));
    let mut show = |p: &trax_emulator::Progress| {
        if let Some(l) = &line {
            l.show(p)
        }
    };
    if line.is_some() {
        req.progress = Some(&mut show);
    }
    req.livelock = if a.stop_on_livelock {
        OnLivelock::Stop
    } else {
        OnLivelock::Warn
    };
    // A livelock the run goes on after is told at once (the run may never end); one
    // that stops it, with the failure.
    let mut tell = |l: &trax_emulator::Livelock| {
        if !l.stopped {
            let text = with_newline(l.render());
            match &line {
                Some(bar) => bar.print(&text),
                None => eprint!("{text}"),
            }
        }
    };
    req.livelock_notice = Some(&mut tell);
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let start = std::time::Instant::now();
    let r = trax_emulator::run(req, &mut out);
    if let Some(l) = &line {
        l.finish();
    }
    let mut r = r.map_err(|e| format!("{}: {e}", prepared.name))?;
    let _ = out.flush();
    let secs = start.elapsed().as_secs_f64();
    for w in &r.warnings {
        eprintln!("warning: {w}");
    }
    match &r.timing {
        None if r.sampled.is_some() => {
            if let Some(s) = &r.sampled {
                eprint!("{}", s.summary());
            }
            eprint!("{}", scene_report(&prepared.image));
            eprintln!(
                "simulated (sampled) in {secs:.3} s on {} host thread(s)",
                r.host_threads
            );
        }
        None => {
            let n = r.instructions;
            eprintln!(
                "{n} instructions in {secs:.3} s ({:.1} M instr/s), {} thread(s), functional",
                n as f64 / secs.max(1e-9) / 1e6,
                r.threads
            );
            if r.rays() > 0 {
                eprintln!("rays: {}", r.rays());
            }
            if let Some(line) = trax_runtime::counters::summary(&r.counters) {
                eprintln!("{line}");
            }
            eprint!("{}", scene_report(&prepared.image));
        }
        Some(stats) => {
            eprint!("{}", with_newline(stats.summary()));
            if let Some(line) = trax_runtime::counters::summary(&r.counters) {
                eprintln!("{line}");
            }
            eprint!("{}", scene_report(&prepared.image));
            eprintln!(
                "simulated in {secs:.3} s on {} host thread(s)",
                r.host_threads
            );
        }
    }
    let intervals = spool
        .take()
        .map(trax::stats::IntervalSpool::finish)
        .transpose()
        .map_err(|e| format!("statistics intervals: {e}"))?;
    if let Some(path) = &a.stats_json {
        let doc = StatsDocument::new(
            &request,
            &prepared,
            &r,
            &chip,
            a.quantum,
            limits,
            intervals.as_ref(),
        );
        write_json(path, &doc).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if r.finished() && (a.png.output.is_some() || a.raw_framebuffer.is_some()) {
        let bytes = prepared.framebuffer(&r).unwrap_or_default();
        a.png.write(&bytes, p.render.width, p.render.height)?;
        if let Some(path) = &a.raw_framebuffer {
            std::fs::write(path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    let code = match &r.failure {
        None => ExitCode::SUCCESS,
        Some(text) => {
            eprint!("{}", with_newline(text.clone()));
            ExitCode::FAILURE
        }
    };
    let profile = r.profile.take().map(|p| (p, r.debug.take()));
    Ok(Executed { code, profile })
}

/// Writes `doc` as pretty JSON to `path`, streamed (the intervals are read from their
/// spool as they are written).
fn write_json(path: &std::path::Path, doc: &StatsDocument) -> std::io::Result<()> {
    use std::io::Write;
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    serde_json::to_writer_pretty(&mut w, doc)?;
    w.write_all(b"\n")?;
    w.flush()
}

/// Refuses an output path that cannot be written (a directory, a read-only file or
/// directory) before a run whose results would be lost: opens it for writing without
/// truncating it, and removes it again when it did not exist.
fn check_writable(path: &std::path::Path) -> Result<(), String> {
    if path.is_dir() {
        return Err(format!("{}: is a directory, not a file", path.display()));
    }
    let existed = path.exists();
    std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .map_err(|e| format!("{}: cannot be written: {e}", path.display()))?;
    if !existed {
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

fn with_newline(mut s: String) -> String {
    if !s.ends_with('\n') {
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::flamegraph_svg;

    /// `f::g` sorts between `f` and `f;h` as a string; ordered as strings, `a;f` would be
    /// drawn as two boxes (1 and 3) instead of one of 4.
    #[test]
    fn flamegraph_draws_one_box_per_call_path() {
        let folded = "a;f 1\na;f::g 2\na;f;h 3\n";
        let svg = flamegraph_svg(folded, "instructions", "t").unwrap();
        let boxes = |name: &str| svg.matches(&format!("<title>{name} (")).count();
        assert_eq!(boxes("f"), 1, "{svg}");
        assert!(svg.contains("<title>f (4 instructions, 66.67%)</title>"));
        assert!(svg.contains("<title>f::g (2 instructions, 33.33%)</title>"));
        assert!(svg.contains("<title>h (3 instructions, 50.00%)</title>"));
        assert!(svg.contains("<title>a (6 instructions, 100.00%)</title>"));
        assert!(flamegraph_svg("", "instructions", "t").is_err());
    }
}
