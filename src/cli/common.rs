//! Flag groups shared by the subcommands that run kernels (`trax run`, `trax annotate`,
//! `trax native`).

use std::path::{Path, PathBuf};

use clap::Args;
use trax::pipeline::Request;
use trax_assembler::image::RenderOptions;
use trax_assembler::scene::LoadOptions;
use trax_emulator::timing::sample::{DEFAULT_WARMUP, DEFAULT_WINDOW};
use trax_emulator::timing::{ChipConfig, SampleRequest, DEFAULT_CHIP};

/// The chip and its thread shape.
#[derive(Args, Debug, Clone)]
pub struct ShapeArgs {
    /// Chip configuration: a preset (`tiny`, `baseline`, `baseline-ch3`, `strata`,
    /// `baseline-ch5`, `strata-plus`; `trax config list` describes them, `trax config show
    /// NAME` prints one in full) or a TOML file (which may start with `preset = "NAME"` and
    /// set only what differs).
    #[arg(long, default_value = DEFAULT_CHIP)]
    pub config: String,
    /// Thread multiprocessors (overrides the config).
    #[arg(long)]
    pub tms: Option<u32>,
    /// Threads per TM (overrides the config).
    #[arg(long)]
    pub threads: Option<u32>,
    /// Set any chip config field by its dotted path, as a line of the config file would
    /// (`--set memory.l2.capacity_bytes=262144`, `--set memory.dram.preset=hbm2`,
    /// `--set treelets.align=dram-row`); VALUE is TOML (a bare word is a string).
    /// Repeatable; applied before `--tms/--threads/--l2s`.
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = super::run::parse_set)]
    pub set: Vec<(String, toml::Value)>,
}

/// How a sampled run samples (`trax run --sample N`, `trax ladder --rates`).
#[derive(Args, Debug, Clone, Default)]
pub struct SampleArgs {
    /// Sampling: detailed cycles before each window's measurement (default 2000, at least
    /// 1000).
    #[arg(long, value_name = "CYCLES")]
    pub sample_warmup: Option<u64>,
    /// Sampling: measured cycles of each window (default 8000, at least the warm-up).
    #[arg(long, value_name = "CYCLES")]
    pub sample_window: Option<u64>,
    /// Sampling: the global register the kernel takes its work items from (default: the
    /// one the kernel declares with `trax::declare_work`, as every example does, or else
    /// 255, that of `trax::scene::pixel_share`).
    #[arg(long, value_name = "REG")]
    pub sample_counter: Option<u32>,
    /// Sampling: the work items the counter hands out in the run (default: as the kernel
    /// declares, or else the image's pixels).
    #[arg(long, value_name = "N")]
    pub sample_items: Option<u32>,
    /// Sampling: seed of the windows' positions (default 1).
    #[arg(long, value_name = "S")]
    pub sample_seed: Option<u32>,
}

impl SampleArgs {
    /// The request for `windows` windows over a frame of `pixels` pixels on `chip`,
    /// checked ([`SampleRequest::check`]: refused settings name the flag).
    pub fn request(
        &self,
        windows: u32,
        pixels: u32,
        chip: &ChipConfig,
    ) -> Result<SampleRequest, String> {
        let r = SampleRequest {
            windows,
            warmup_cycles: self.sample_warmup.unwrap_or(DEFAULT_WARMUP),
            measure_cycles: self.sample_window.unwrap_or(DEFAULT_WINDOW),
            counter: self.sample_counter,
            items: self.sample_items,
            pixels,
            seed: self.sample_seed.unwrap_or(1),
        };
        r.check(chip.tms.saturating_mul(chip.threads_per_tm))?;
        Ok(r)
    }

    /// An error naming a sampling flag given without sampling.
    pub fn unused(&self) -> Result<(), String> {
        let given = [
            ("--sample-warmup", self.sample_warmup.is_some()),
            ("--sample-window", self.sample_window.is_some()),
            ("--sample-counter", self.sample_counter.is_some()),
            ("--sample-items", self.sample_items.is_some()),
            ("--sample-seed", self.sample_seed.is_some()),
        ];
        match given.iter().find(|(_, on)| *on) {
            Some((flag, _)) => Err(format!("{flag} needs --sample N (a sampled run)")),
            None => Ok(()),
        }
    }
}

/// Scene and image parameters.
#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene: `cornell` (embedded default), `procedural:N` (about N triangles),
    /// `icosphere:N` (a closed sphere mesh of 20·4^N triangles), `hairball:N[:SEED]`,
    /// `vegetation:N[:SEED]`, `box:SCENE`, `subdivide:N:SCENE`, or an .obj/.objl file
    /// (details: `trax scene --help`).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Scale the whole scene by this factor (e.g. 1e-20 or 1e20): vertices, camera eye and
    /// point-light positions, after the .view/.light files are applied. Directions and the
    /// image window are kept, so a scale-invariant kernel draws the same image; point lights
    /// keep their intensity (with a 1/d² falloff they look 1/S² as bright).
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub scene_scale: Option<f64>,
    /// Camera file (simtrax .view); default: beside the scene file, or framing the scene.
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Light file (simtrax .light: the position, then optionally an intensity or an RGB
    /// intensity; 1 without); default: beside the scene file.
    #[arg(long)]
    pub light: Option<PathBuf>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 128)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 128)]
    pub height: u32,
    /// Samples per pixel (header field `spp`), at least 1.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: u32,
    /// Maximum path depth (header field `max_depth`).
    #[arg(long, default_value_t = 4)]
    pub depth: u32,
    /// Seed of the random streams (per thread at start-up; per pixel and sample after
    /// `trax::seed_pixel`).
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Keep the loaded scene in DIR and read it from there next time, unless a file it was
    /// read from has changed since (checked by SHA-256): runs that share a large scene
    /// parse it once. Keep one DIR per trax build (`trax sweep` does).
    #[arg(long, value_name = "DIR")]
    pub scene_cache: Option<PathBuf>,
}

impl RenderArgs {
    /// The pipeline request for `kernel` built at `opt_level`, to run on `chip`.
    pub fn request(&self, kernel: &Path, opt_level: u8, chip: &ChipConfig) -> Request {
        Request {
            kernel: kernel.to_path_buf(),
            more: Vec::new(),
            opt_level,
            scene: self.scene.clone(),
            load: self.load_options(),
            render: self.render_options(),
            chip: chip.clone(),
            scene_cache: self.scene_cache.clone(),
        }
    }

    /// Scene loader options.
    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            view: self.view.clone(),
            light: self.light.clone(),
            scale: self.scene_scale,
            max_triangles: None,
        }
    }

    /// Header parameters for the image builder.
    pub fn render_options(&self) -> RenderOptions {
        RenderOptions {
            width: self.width,
            height: self.height,
            spp: self.spp,
            max_depth: self.depth,
            seed: self.seed,
            ..RenderOptions::default()
        }
    }
}

/// `--exposure auto|EV`: how the PNG scales the linear framebuffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exposure {
    /// [`trax_runtime::host::auto_exposure`]: dark images brightened by whole stops.
    Auto,
    /// This many stops (each doubles the values; negative darkens).
    Ev(f32),
}

impl Exposure {
    /// Parses `auto` or a number of stops (-40..=40).
    pub fn parse(s: &str) -> Result<Exposure, String> {
        if s == "auto" {
            return Ok(Exposure::Auto);
        }
        match s.parse::<f32>() {
            Ok(ev) if (-40.0..=40.0).contains(&ev) => Ok(Exposure::Ev(ev)),
            _ => Err(format!(
                "{s:?}: expected `auto` or a number of stops from -40 to 40 (e.g. 2.5)"
            )),
        }
    }

    /// The stops for framebuffer `fb` (little-endian f32 RGB).
    pub fn stops(self, fb: &[u8]) -> f32 {
        match self {
            Exposure::Auto => trax_runtime::host::auto_exposure(fb),
            Exposure::Ev(ev) => ev,
        }
    }
}

/// The PNG flags of `trax run` and `trax native`.
#[derive(Args, Debug, Clone)]
pub struct PngArgs {
    /// Write the framebuffer as PNG (top row first; each linear value times 2^EXPOSURE,
    /// clamped to [0, 1], no gamma curve).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// The PNG's exposure: `auto` (default) brightens a dark image by whole stops,
    /// floor(log2(0.18 / mean)) where mean is the framebuffer's mean value, and leaves one
    /// whose mean is at least 0.09 as it is; or EV, a number of stops (0: the values as
    /// they are). The raw framebuffer (--raw-framebuffer, trax compare) is never changed.
    #[arg(long, value_name = "auto|EV", default_value = "auto", value_parser = Exposure::parse)]
    pub exposure: Exposure,
}

impl PngArgs {
    /// Writes framebuffer `fb` as the PNG (if asked for) and says so with its exposure.
    pub fn write(&self, fb: &[u8], width: u32, height: u32) -> Result<(), String> {
        let Some(path) = &self.output else {
            return Ok(());
        };
        let ev = self.exposure.stops(fb);
        let rgb = trax_runtime::host::framebuffer_rgb8_exposed(fb, width, height, ev);
        super::native::write_png(path, width, height, &rgb).map_err(|e| e.to_string())?;
        let auto = if self.exposure == Exposure::Auto {
            "auto, "
        } else {
            ""
        };
        eprintln!("wrote {} (exposure {auto}{ev:+} EV)", path.display());
        Ok(())
    }
}
