//! The statistics document of a run (`trax run --stats-json FILE`), schema 1: one shape
//! for both modes (fields a mode does not measure are `null`). Every field is described in
//! `docs/STATS.md`; `tests/stats_json.rs` checks that list against real output of both
//! modes. The sweep (`trax sweep`) reads these documents (`src/cli/sweep/metrics.rs`).
//!
//! These are mirror types, built at the edge from the run's inputs and its report; the
//! emulator's statistics records ([`TimingStats`]) are embedded as the `timing` object.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Seek, SeekFrom, Write};

use serde::Serialize;
use trax_assembler::image::SceneImage;
use trax_assembler::scene::Source;
use trax_emulator::timing::{ChipConfig, Interval, SampledStats, TimingStats};
use trax_emulator::{Outcome, RunReport};

use crate::pipeline::{left_out, KernelFile, Prepared, Request};

/// The schema version written as `schema`; it changes when a field changes meaning or
/// goes away (new fields may be added within a version).
pub const SCHEMA: u32 = 1;

/// The `timing` object: the run's [`TimingStats`] and its intervals.
#[derive(Debug, Serialize)]
pub struct TimingDoc<'a> {
    /// The statistics.
    #[serde(flatten)]
    pub stats: &'a TimingStats,
    /// `timing.intervals`: the run over time (`[]` without `--stats-interval`).
    pub intervals: Intervals<'a>,
}

/// The intervals of a run as a JSON array, read one at a time from their spool file
/// ([`IntervalSpool::finish`]), so writing the document holds one interval in memory.
#[derive(Debug)]
pub struct Intervals<'a>(pub Option<&'a File>);

impl Serialize for Intervals<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::{Error, SerializeSeq};
        let mut seq = s.serialize_seq(None)?;
        if let Some(mut f) = self.0 {
            f.seek(SeekFrom::Start(0)).map_err(S::Error::custom)?;
            for line in BufReader::new(f).lines() {
                let line = line.map_err(S::Error::custom)?;
                // As written (exact floats, field order): one interval per line.
                let v: Box<serde_json::value::RawValue> =
                    serde_json::from_str(&line).map_err(S::Error::custom)?;
                seq.serialize_element(&v)?;
            }
        }
        seq.end()
    }
}

/// The intervals of a timing run (`--stats-interval`), written as they complete to an
/// unnamed temporary file (created in the system's temporary directory and unlinked at
/// once, so nothing is left behind even when the process is killed): the run's memory does
/// not grow with their number.
pub struct IntervalSpool {
    out: BufWriter<File>,
    error: Option<std::io::Error>,
}

impl IntervalSpool {
    /// An empty spool.
    pub fn new() -> std::io::Result<IntervalSpool> {
        let dir = std::env::temp_dir();
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path = dir.join(format!("trax-intervals-{}-{nanos}", std::process::id()));
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(&path)
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        std::fs::remove_file(&path)?;
        Ok(IntervalSpool {
            out: BufWriter::new(file),
            error: None,
        })
    }

    /// Appends one interval (the first write error is kept for [`Self::finish`]).
    pub fn push(&mut self, iv: &Interval) {
        if self.error.is_some() {
            return;
        }
        let r = serde_json::to_writer(&mut self.out, iv)
            .map_err(std::io::Error::from)
            .and_then(|()| self.out.write_all(b"\n"));
        if let Err(e) = r {
            self.error = Some(e);
        }
    }

    /// The spool file with every interval, one JSON object a line.
    pub fn finish(self) -> std::io::Result<File> {
        if let Some(e) = self.error {
            return Err(e);
        }
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

/// The whole document.
#[derive(Debug, Serialize)]
pub struct StatsDocument<'a> {
    /// [`SCHEMA`].
    pub schema: u32,
    /// `functional`, `timing` or `sampled`.
    pub mode: &'static str,
    /// How the run ended (see [`outcome_name`]).
    pub outcome: &'static str,
    /// The trax version that wrote it.
    pub trax_version: &'static str,
    /// What was run, with what.
    pub inputs: Inputs,
    /// The chip as configured (every field of a chip config file).
    pub chip: &'a ChipConfig,
    /// Hardware threads (TMs x threads per TM).
    pub threads: u32,
    /// Functional and sampled: instructions retired (executed). Timing: instructions
    /// issued, without zero-cost debug ops (`timing.debug_ops`).
    pub instructions: u64,
    /// Rays (`trax.stat 0`).
    pub rays: u64,
    /// The `trax.stat` counters.
    pub counters: &'a [u64],
    /// Core cycles until the last thread halted (timing), `null` in functional and
    /// sampled mode (a sampled run estimates them: `sampled.estimates.cycles`).
    pub cycles: Option<u64>,
    /// Timing-model statistics, `null` in functional and sampled mode.
    pub timing: Option<TimingDoc<'a>>,
    /// A sampled run's estimates with confidence intervals, costs and parameters (`null`
    /// unless `--sample`).
    pub sampled: Option<&'a SampledStats>,
    /// The scene data in memory.
    pub scene: SceneData,
    /// Where the threads were when a limit or a livelock stopped the run (`null`
    /// otherwise).
    pub threads_at_stop: Option<&'a trax_emulator::ThreadPlaces>,
    /// The livelock found during the run (`null`: none).
    pub livelock: Option<&'a trax_emulator::Livelock>,
}

/// The run's inputs.
#[derive(Debug, Serialize)]
pub struct Inputs {
    /// The kernel as named on the command line.
    pub kernel: String,
    /// Optimisation level it was built at (`null`: a prebuilt executable).
    pub opt_level: Option<u8>,
    /// The scene as named.
    pub scene: String,
    /// `--scene-scale` (`null`: not scaled).
    pub scene_scale: Option<f64>,
    /// `--view` file (`null`: beside the scene file, or framing the scene).
    pub view: Option<String>,
    /// `--light` file (`null`: beside the scene file).
    pub light: Option<String>,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum path depth.
    pub depth: u32,
    /// Random seed.
    pub seed: u32,
    /// Functional mode's interleaving quantum (`null` in timing mode).
    pub quantum: Option<u32>,
    /// `--max-instructions` (`null`: none).
    pub max_instructions: Option<u64>,
    /// `--max-cycles` (`null`: none).
    pub max_cycles: Option<u64>,
    /// The files the scene was loaded from, each `{"path", "sha256"}`, and those looked for
    /// and not found (`{"path", "absent": true}`: a material library, a `.view`/`.light`
    /// beside the scene file) or listed (`{"dir", "ext", "names"}`: the only `.view` of a
    /// directory is the camera). Empty for built-in scenes. `trax sweep` compares them with
    /// the files as they are now to tell a stale result.
    pub scene_files: Vec<serde_json::Value>,
}

/// A scene source as JSON ([`Inputs::scene_files`]).
pub fn source_json(s: &Source) -> serde_json::Value {
    match s {
        Source::Read { path, sha256 } => {
            serde_json::json!({ "path": path.display().to_string(), "sha256": sha256 })
        }
        Source::Absent { path } => {
            serde_json::json!({ "path": path.display().to_string(), "absent": true })
        }
        Source::Listing { dir, ext, names } => {
            serde_json::json!({ "dir": dir.display().to_string(), "ext": ext, "names": names })
        }
    }
}

/// A scene source from its JSON ([`source_json`]); `None` if it is not one.
pub fn source_from_json(v: &serde_json::Value) -> Option<Source> {
    let s = |k: &str| v.get(k).and_then(serde_json::Value::as_str);
    if let (Some(path), Some(sha256)) = (s("path"), s("sha256")) {
        return Some(Source::Read {
            path: path.into(),
            sha256: sha256.to_string(),
        });
    }
    if let (Some(path), Some(true)) = (s("path"), v.get("absent").and_then(|a| a.as_bool())) {
        return Some(Source::Absent { path: path.into() });
    }
    let names = v.get("names")?.as_array()?;
    Some(Source::Listing {
        dir: s("dir")?.into(),
        ext: s("ext")?.to_string(),
        names: names
            .iter()
            .map(|n| n.as_str().map(str::to_string))
            .collect::<Option<_>>()?,
    })
}

/// The scene data of the memory image.
#[derive(Debug, Serialize)]
pub struct SceneData {
    /// Bytes of all placed components.
    pub bytes: u64,
    /// The placed components, in address order.
    pub components: Vec<Component>,
    /// Optional components left out (the kernel never references them).
    pub left_out: Vec<&'static str>,
}

/// One placed scene component.
#[derive(Debug, Serialize)]
pub struct Component {
    /// Header field name.
    pub name: &'static str,
    /// Address.
    pub addr: u32,
    /// Elements.
    pub count: u32,
    /// Bytes.
    pub bytes: u32,
}

/// `finished`, `crashed`, `deadlock`, `instruction_limit`, `cycle_limit` or `livelock`.
pub fn outcome_name(o: &Outcome) -> &'static str {
    match o {
        Outcome::Finished => "finished",
        Outcome::Crashed(_) => "crashed",
        Outcome::Deadlock { .. } => "deadlock",
        Outcome::InstructionLimit => "instruction_limit",
        Outcome::CycleLimit => "cycle_limit",
        Outcome::Livelock => "livelock",
    }
}

impl SceneData {
    /// The scene data of `image`.
    pub fn of(image: &SceneImage) -> SceneData {
        SceneData {
            bytes: image.scene_bytes(),
            components: image
                .components
                .iter()
                .map(|c| Component {
                    name: c.name,
                    addr: c.addr,
                    count: c.count,
                    bytes: c.bytes,
                })
                .collect(),
            left_out: left_out(image),
        }
    }
}

impl<'a> StatsDocument<'a> {
    /// The document of `run` of `prepared` (from `req`), with the limits and quantum it
    /// ran under.
    pub fn new(
        req: &Request,
        prepared: &Prepared,
        run: &'a RunReport,
        chip: &'a ChipConfig,
        quantum: u32,
        limits: trax_emulator::Limits,
        intervals: Option<&'a File>,
    ) -> StatsDocument<'a> {
        let functional = run.mode == trax_emulator::Mode::Functional;
        let path = |p: &Option<std::path::PathBuf>| p.as_ref().map(|p| p.display().to_string());
        StatsDocument {
            schema: SCHEMA,
            mode: if run.sampled.is_some() {
                "sampled"
            } else {
                run.mode.name()
            },
            outcome: outcome_name(&run.outcome),
            trax_version: env!("CARGO_PKG_VERSION"),
            inputs: Inputs {
                kernel: req.kernel.display().to_string(),
                opt_level: req
                    .files()
                    .iter()
                    .any(|f| KernelFile::of(f).is_source())
                    .then_some(req.opt_level),
                scene: req.scene.clone(),
                scene_scale: req.load.scale,
                view: path(&req.load.view),
                light: path(&req.load.light),
                width: req.render.width,
                height: req.render.height,
                spp: req.render.spp,
                depth: req.render.max_depth,
                seed: req.render.seed,
                quantum: functional.then_some(quantum),
                max_instructions: limits.max_instructions,
                max_cycles: limits.max_cycles,
                scene_files: prepared.scene_sources.iter().map(source_json).collect(),
            },
            chip,
            threads: run.threads,
            instructions: run.instructions,
            rays: run.rays(),
            counters: &run.counters,
            cycles: run.cycles,
            timing: run.timing.as_ref().map(|stats| TimingDoc {
                stats,
                intervals: Intervals(intervals),
            }),
            sampled: run.sampled.as_ref(),
            scene: SceneData::of(&prepared.image),
            threads_at_stop: run.stopped_at.as_ref(),
            livelock: run.livelock.as_ref(),
        }
    }
}
