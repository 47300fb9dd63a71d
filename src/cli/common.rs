//! Flag groups shared by the subcommands that run kernels (`trax run`, `trax native`).

use std::path::PathBuf;

use clap::Args;
use trax_assembler::image::{on_demand_components, RenderOptions, SceneImage};
use trax_assembler::scene::LoadOptions;
use trax_emulator::timing::ChipConfig;

/// Scene and image parameters.
#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene: `cornell` (embedded default), `procedural:N` (about N triangles),
    /// `icosphere:N` (a closed sphere mesh of 20·4^N triangles), or an .obj/.objl file.
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

    /// Rejects zero-sized images.
    pub fn validate(&self) -> Result<(), String> {
        for (flag, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 {
                return Err(format!("--{flag} must be at least 1"));
            }
        }
        Ok(())
    }
}

/// The chip: preset or TOML file `config` with the command-line overrides applied (`l2s`:
/// number of L2s, TMs split evenly among them).
pub fn chip_config(
    config: &str,
    sets: &[(String, toml::Value)],
    tms: Option<u32>,
    threads: Option<u32>,
    l2s: Option<u32>,
) -> Result<ChipConfig, String> {
    let mut chip = ChipConfig::load(config).map_err(|e| e.to_string())?;
    chip.apply_overrides(sets).map_err(|e| e.to_string())?;
    for (flag, v) in [("tms", tms), ("threads", threads), ("l2s", l2s)] {
        if v == Some(0) {
            return Err(format!("--{flag} must be at least 1"));
        }
    }
    if let Some(t) = tms {
        chip.tms = t;
    }
    if let Some(t) = threads {
        chip.threads_per_tm = t;
    }
    if let Some(l2s) = l2s {
        if l2s > chip.tms {
            return Err(format!("--l2s {l2s} is more than the {} TMs", chip.tms));
        }
        chip.tms_per_l2 = chip.tms.div_ceil(l2s);
    }
    chip.validate().map_err(|e| e.to_string())?;
    Ok(chip)
}

/// The optional scene components the image leaves out: the kernel never references them
/// (components are linked on demand, see `trax_assembler::image`).
pub fn left_out(image: &SceneImage) -> Vec<&'static str> {
    on_demand_components()
        .into_iter()
        .filter(|c| image.component(c).is_none())
        .collect()
}

/// The scene-data lines of a run summary: every placed component's bytes, then what was
/// left out.
pub fn scene_report(image: &SceneImage) -> String {
    let mut s = format!(
        "scene data: {} bytes in {} components\n",
        image.scene_bytes(),
        image.components.len()
    );
    for c in &image.components {
        s += &format!(
            "   {:<13} {:>12} bytes {:>10} elements\n",
            c.name, c.bytes, c.count
        );
    }
    let out = left_out(image);
    if out.is_empty() {
        s += "   left out: none (the kernel references every component)\n";
    } else {
        s += &format!(
            "   left out (never referenced by the kernel): {}\n",
            out.join(", ")
        );
    }
    s
}

/// The scene data as JSON: `{"bytes", "components": [{"name", "addr", "count", "bytes"}],
/// "left_out": [names]}`.
pub fn scene_json(image: &SceneImage) -> serde_json::Value {
    serde_json::json!({
        "bytes": image.scene_bytes(),
        "components": image
            .components
            .iter()
            .map(|c| serde_json::json!({
                "name": c.name,
                "addr": c.addr,
                "count": c.count,
                "bytes": c.bytes,
            }))
            .collect::<Vec<_>>(),
        "left_out": left_out(image),
    })
}
