//! `trax native`: builds a kernel with rustc against the host implementation of the
//! prelude and runs it on host threads — a fast functional reference for the emulator.
//! The build and the run are the library's (`trax::native`); this module parses the
//! arguments and writes the PNG.
//!
//! The machine matches `trax run`'s: the thread shape comes from the same chip config
//! (`--config`, default `trax_emulator::timing::DEFAULT_CHIP`, with `--tms`/`--threads` overrides), and the
//! memory image holds the scene components `trax run` would lay out — the kernel is also
//! built with the trax compiler (as `trax run` does, at `-O2`) to learn which header
//! fields it references — so per-triangle data is in the same order (BVH leaf order only
//! when the kernel reads the BVH) and images are identical.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use super::common::{PngArgs, RenderArgs, ShapeArgs};
use trax::native::{self, HostShape, NativeError};
use trax::pipeline::{self, chip_config, scene_report, DEFAULT_OPT_LEVEL};

/// Arguments of `trax native`.
#[derive(Args, Debug)]
pub struct NativeArgs {
    /// The kernel source: TRaX-Rust (`fn trax_main()`), or C/C++ (`void trax_main(void)`,
    /// compiled for the host by clang with `trax.h`'s host side).
    pub kernel: PathBuf,
    /// Further C and C++ sources linked with the kernel (as for `trax run`); their
    /// constructors run on every kernel thread before `trax_main`, as on the machine.
    #[arg(value_name = "MORE")]
    pub more: Vec<PathBuf>,
    /// Scene and image parameters.
    #[command(flatten)]
    pub render: RenderArgs,
    /// The chip whose thread shape (TMs x threads) to run, as for `trax run`.
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// The PNG and its exposure.
    #[command(flatten)]
    pub png: PngArgs,
    /// Also write the raw framebuffer: `width*height` pixels of 3 little-endian f32.
    #[arg(long)]
    pub raw_framebuffer: Option<PathBuf>,
}

/// What went wrong in `trax native`: the build or run, or the command line.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{0}")]
    Native(#[from] NativeError),
    #[error("--{flag} must be at least 1")]
    BadFlag { flag: &'static str },
    #[error("{0}")]
    Chip(String),
    #[error("--tms × --threads = {0} is more than the host runner supports (4096)")]
    TooManyThreads(u64),
    #[error("{path}: {message}")]
    Output { path: String, message: String },
    /// Writing the PNG (the message names the file).
    #[error("{0}")]
    Png(String),
}

/// Runs `trax native`.
pub fn run(a: NativeArgs) -> ExitCode {
    match native(&a) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn native(a: &NativeArgs) -> Result<(), Error> {
    for (flag, v) in [("width", a.render.width), ("height", a.render.height)] {
        if v == 0 {
            return Err(Error::BadFlag { flag });
        }
    }
    let s = &a.shape;
    let chip = chip_config(&s.config, &s.set, s.tms, s.threads, None).map_err(Error::Chip)?;
    let (tms, threads) = (chip.tms, chip.threads_per_tm);
    let total = tms as u64 * threads as u64;
    if total > 4096 {
        return Err(Error::TooManyThreads(total));
    }
    for out in a.png.output.iter().chain(&a.raw_framebuffer) {
        check_writable(out)?;
    }
    // rustc first: a kernel it rejects gets rustc's diagnostics and nothing else.
    let exe = native::build_program(&a.kernel, &a.more)?;
    let mut request = a.render.request(&a.kernel, DEFAULT_OPT_LEVEL, &chip);
    request.more = a.more.clone();
    let (scene_image, warnings) = pipeline::scene_image(&request).map_err(NativeError::from)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let shape = HostShape {
        tms,
        threads,
        schedule: chip.stream_memory.schedule.name(),
        spill: chip.stream_memory.geometry().spill.map(|g| g.to_arg()),
    };
    let fb = native::run_kernel(&exe, &a.kernel, &scene_image.memory, &shape)?;
    eprint!("{}", scene_report(&scene_image));
    let bytes = fb
        .segments
        .first()
        .map(|s| s.data.as_slice())
        .unwrap_or(&[]);
    a.png
        .write(bytes, a.render.width, a.render.height)
        .map_err(Error::Png)?;
    if let Some(raw) = &a.raw_framebuffer {
        std::fs::write(raw, bytes).map_err(|e| Error::Output {
            path: raw.display().to_string(),
            message: e.to_string(),
        })?;
    }
    Ok(())
}

/// Fails early (before building and running) if `out` cannot be created.
fn check_writable(out: &Path) -> Result<(), Error> {
    let dir = out.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(d) = dir {
        if !d.is_dir() {
            return Err(Error::Output {
                path: out.display().to_string(),
                message: "the output directory does not exist".into(),
            });
        }
    }
    Ok(())
}

/// Writes 8-bit RGB pixels (`width*height*3` bytes, top row first) as a PNG file.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), Error> {
    let err = |message: String| Error::Output {
        path: path.display().to_string(),
        message,
    };
    let png_err = |e: png::EncodingError| err(format!("cannot write PNG: {e}"));
    let file = std::fs::File::create(path).map_err(|e| err(e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(png_err)?;
    w.write_image_data(rgb).map_err(png_err)?;
    w.finish().map_err(png_err)?;
    Ok(())
}
