//! Flag groups shared by the subcommands that run kernels (`trax run`, `trax annotate`,
//! `trax native`).

use std::path::{Path, PathBuf};

use clap::Args;
use trax::pipeline::Request;
use trax_assembler::image::RenderOptions;
use trax_assembler::scene::LoadOptions;
use trax_emulator::timing::{ChipConfig, DEFAULT_CHIP};

/// The chip and its thread shape.
#[derive(Args, Debug, Clone)]
pub struct ShapeArgs {
    /// Chip configuration: a preset (`tiny`, `baseline`, `strata`, `baseline-ch5`,
    /// `strata-plus`) or a TOML file.
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
    /// Light file (simtrax .light); default: beside the scene file.
    #[arg(long)]
    pub light: Option<PathBuf>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 128)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 128)]
    pub height: u32,
    /// Samples per pixel (header field `spp`).
    #[arg(long, default_value_t = 1)]
    pub spp: u32,
    /// Maximum path depth (header field `max_depth`).
    #[arg(long, default_value_t = 4)]
    pub depth: u32,
    /// Seed of the random streams (per thread at start-up; per pixel and sample after
    /// `trax::seed_pixel`).
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
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
        }
    }

    /// Scene loader options.
    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            view: self.view.clone(),
            light: self.light.clone(),
            scale: self.scene_scale,
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
