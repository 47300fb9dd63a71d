//! The statistics document of a run (`trax run --stats-json FILE`), schema 1: one shape
//! for both modes (fields a mode does not measure are `null`). Every field is described in
//! `docs/STATS.md`; `tests/stats_json.rs` checks that list against real output of both
//! modes. The sweep (`trax sweep`) reads these documents (`src/cli/sweep/metrics.rs`).
//!
//! These are mirror types, built at the edge from the run's inputs and its report; the
//! emulator's statistics records ([`TimingStats`]) are embedded as the `timing` object.

use serde::Serialize;
use trax_assembler::image::SceneImage;
use trax_emulator::timing::{ChipConfig, SampledStats, TimingStats};
use trax_emulator::{Outcome, RunReport};

use crate::pipeline::{left_out, KernelFile, Request};

/// The schema version written as `schema`; it changes when a field changes meaning or
/// goes away (new fields may be added within a version).
pub const SCHEMA: u32 = 1;

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
    pub timing: Option<&'a TimingStats>,
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
    /// The document of `run`, prepared from `req` with memory `image`, with the limits
    /// and quantum it ran under.
    pub fn new(
        req: &Request,
        image: &SceneImage,
        run: &'a RunReport,
        chip: &'a ChipConfig,
        quantum: u32,
        limits: trax_emulator::Limits,
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
            },
            chip,
            threads: run.threads,
            instructions: run.instructions,
            rays: run.rays(),
            counters: &run.counters,
            cycles: run.cycles,
            timing: run.timing.as_ref(),
            sampled: run.sampled.as_ref(),
            scene: SceneData::of(image),
            threads_at_stop: run.stopped_at.as_ref(),
            livelock: run.livelock.as_ref(),
        }
    }
}
